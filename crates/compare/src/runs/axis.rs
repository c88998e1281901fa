//! Evenly spaced values: the frequency axis of a sweep, and each axis of a map.

/// A range of values sampled at `count` evenly spaced points, ends included (`count = 1`:
/// `min` alone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// First value.
    pub min: f64,
    /// Last value (≥ `min`).
    pub max: f64,
    /// Number of values.
    pub count: usize,
}

impl Axis {
    /// The axis from `min` to `max` with `count` values.
    pub fn new(min: f64, max: f64, count: usize) -> Axis {
        Axis { min, max, count }
    }

    /// The values, ascending: `min + (max − min) i/(count − 1)`; the last is exactly `max`.
    pub fn values(&self) -> Vec<f64> {
        match self.count {
            0 => Vec::new(),
            1 => vec![self.min],
            n => {
                let mut v: Vec<f64> = (0..n)
                    .map(|i| self.min + (self.max - self.min) * i as f64 / (n - 1) as f64)
                    .collect();
                v[n - 1] = self.max;
                v
            }
        }
    }

    /// The spacing between neighbouring values (0 for one value).
    pub fn step(&self) -> f64 {
        if self.count > 1 {
            (self.max - self.min) / (self.count - 1) as f64
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_inclusive_and_even() {
        assert_eq!(
            Axis::new(1.0, 2.0, 5).values(),
            vec![1.0, 1.25, 1.5, 1.75, 2.0]
        );
        assert_eq!(Axis::new(1.0, 2.0, 1).values(), vec![1.0]);
        assert!(Axis::new(1.0, 2.0, 0).values().is_empty());
        let v = Axis::new(0.1, 4.0, 400).values();
        assert_eq!(v[399], 4.0);
        assert_eq!(Axis::new(0.0, 1.0, 5).step(), 0.25);
    }
}
