//! The fast paths of [`crate::cycle_equations`]: the unit's stack product (bit for bit
//! nalgebra's, four wide with AVX), its modal flights (from one eigen-decomposition of `A`,
//! remembered per thread for callers whose evaluations share flights) and the exponentials of
//! the doubled matrices that give `∂Φ/∂ω`. The cycle equations are written once for every
//! augmented dimension; these are the pieces that dispatch on it.

use crate::cycle::unit_modes::{ModalForcing, UnitModes};
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, Matrix4, Matrix6, OMatrix, SMatrix};
use std::sync::Arc;

/// Augmented dimension of the unit (two degrees of freedom and the two forcing phases).
pub(super) const UNIT_SIZE: usize = 6;

/// `a b`: for the unit's stack matrices (`D` = 6) by [`unit_product`], bit for bit
/// nalgebra's product at a fraction of its cost; otherwise nalgebra's (whose heap product of
/// larger matrices accumulates in another order).
pub(super) fn product<D: Dim>(a: &OMatrix<f64, D, D>, b: &OMatrix<f64, D, D>) -> OMatrix<f64, D, D>
where
    DefaultAllocator: Allocator<D, D>,
{
    let (rows, columns) = a.shape_generic();
    // One value returned on every path, built in place (no copy of the result).
    let mut out = OMatrix::<f64, D, D>::zeros_generic(rows, columns);
    match (
        <&[f64; 36]>::try_from(a.as_slice()),
        <&[f64; 36]>::try_from(b.as_slice()),
        <&mut [f64; 36]>::try_from(out.as_mut_slice()),
    ) {
        (Ok(x), Ok(y), Ok(c)) if D::try_to_usize() == Some(UNIT_SIZE) => unit_product(x, y, c),
        // nalgebra's `a * b`: the same `gemm` with `α = 1`, `β = 0` (the result is not read).
        _ => a.mul_to(b, &mut out),
    }
    out
}

/// The product `c` of two 6 × 6 column-major matrices, each entry accumulated as nalgebra's
/// product of stack matrices does (`c_ij = a_i0 b_0j`, then `c_ij + a_ik b_kj` for
/// `k = 1 … 5` in order, no fused multiply-add): the same bits, unrolled on the stack. A
/// column of `c` is the columns of `a` weighted by a column of `b`. With AVX at run time the
/// same operations are packed four wide ([`unit_product_avx`]): the same bits.
#[inline]
fn unit_product(a: &[f64; 36], b: &[f64; 36], c: &mut [f64; 36]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX (checked just above), the only requirement of the
        // `target_feature` function.
        unsafe { unit_product_avx(a, b, c) };
        return;
    }
    unit_product_lanes(a, b, c);
}

/// [`unit_product_lanes`] with AVX intrinsics: rows 0–3 of a column four wide, rows 4–5 two
/// wide, the same multiplications and additions in the same order (no FMA: each product and
/// sum rounds as the scalar one does). The paper unit's continuation spent 16 % of its CPU
/// in the two-wide form.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn unit_product_avx(a: &[f64; 36], b: &[f64; 36], c: &mut [f64; 36]) {
    use std::arch::x86_64::*;
    // SAFETY: every load and store stays within the 36 entries of its array (columns of 6
    // from offsets 0, 6, … 30: rows 0–3 from the offset, rows 4–5 from offset + 4); the
    // unaligned forms need no alignment.
    unsafe {
        let pa = a.as_ptr();
        let high: [__m256d; 6] = std::array::from_fn(|k| _mm256_loadu_pd(pa.add(6 * k)));
        let low: [__m128d; 6] = std::array::from_fn(|k| _mm_loadu_pd(pa.add(6 * k + 4)));
        for j in 0..6 {
            let w = &b[6 * j..6 * j + 6];
            let mut sum_high = _mm256_mul_pd(high[0], _mm256_set1_pd(w[0]));
            let mut sum_low = _mm_mul_pd(low[0], _mm_set1_pd(w[0]));
            for k in 1..6 {
                sum_high = _mm256_add_pd(sum_high, _mm256_mul_pd(high[k], _mm256_set1_pd(w[k])));
                sum_low = _mm_add_pd(sum_low, _mm_mul_pd(low[k], _mm_set1_pd(w[k])));
            }
            let out = c.as_mut_ptr().add(6 * j);
            _mm256_storeu_pd(out, sum_high);
            _mm_storeu_pd(out.add(4), sum_low);
        }
    }
}

/// The body of [`unit_product`] without AVX.
#[inline(always)]
fn unit_product_lanes(a: &[f64; 36], b: &[f64; 36], c: &mut [f64; 36]) {
    for (column, weights) in c.chunks_exact_mut(6).zip(b.chunks_exact(6)) {
        let mut sum = [0.0; 6];
        for (s, &v) in sum.iter_mut().zip(&a[0..6]) {
            *s = v * weights[0];
        }
        for k in 1..6 {
            for (s, &v) in sum.iter_mut().zip(&a[6 * k..6 * k + 6]) {
                *s += v * weights[k];
            }
        }
        column.copy_from_slice(&sum);
    }
}

/// A unit-sized augmented matrix on the stack (`m` must be 6 × 6).
pub(super) fn to_unit<D: Dim>(m: &OMatrix<f64, D, D>) -> Matrix6<f64>
where
    DefaultAllocator: Allocator<D, D>,
{
    unit_from_columns(m.as_slice())
}

/// The 6 × 6 matrix of the column-major entries `columns` (outside the generic functions,
/// whose allocator bounds hide the fixed-size constructors).
pub(super) fn unit_from_columns(columns: &[f64]) -> Matrix6<f64> {
    Matrix6::from_column_slice(columns)
}

/// How many modal flights a thread remembers ([`remembered_flow`]). A boundary curve's
/// corrector evaluates, per Newton iteration, the cycle at `Y` and at `Y` moved by its
/// difference steps: moving `α` or the parameter (the gap, the restitution) leaves every
/// flight as it was, moving an impact phase leaves all but two; between the evaluation at `Y`
/// and the parameter's two steps come the phases' and `ω`'s, which add at most
/// `2 · 2 (n − 1) + 2n = 20` new flights for the `n = 4` impacts the study follows: 32 keep
/// the flights at `Y` until they are asked again.
const REMEMBERED_FLIGHTS: usize = 32;

/// One flight of [`REMEMBERED_FLIGHTS`]: its decomposition (held, so that its address names
/// it), forcing and duration, and its flow.
struct RememberedFlight {
    modes: Arc<UnitModes>,
    forcing: ModalForcing,
    tau: u64,
    flow: Matrix6<f64>,
}

thread_local! {
    /// The last [`REMEMBERED_FLIGHTS`] modal flights computed on this thread, and where the
    /// next one goes.
    static FLIGHTS: std::cell::RefCell<(usize, Vec<RememberedFlight>)> =
        const { std::cell::RefCell::new((0, Vec::new())) };
}

/// `modes.flow(forcing, tau)`, or the same flow computed earlier on this thread from the same
/// decomposition, forcing and duration (bit for bit: the flow is a function of these alone).
pub(super) fn remembered_flow(
    modes: &Arc<UnitModes>,
    forcing: &ModalForcing,
    tau: f64,
) -> Matrix6<f64> {
    let tau_bits = tau.to_bits();
    FLIGHTS.with(|cell| {
        let mut memory = cell.borrow_mut();
        let (next, flights) = &mut *memory;
        if let Some(hit) = flights.iter().find(|f| {
            f.tau == tau_bits && Arc::ptr_eq(&f.modes, modes) && f.forcing.same_bits(forcing)
        }) {
            return hit.flow;
        }
        let flow = modes.flow(forcing, tau);
        let entry = RememberedFlight {
            modes: Arc::clone(modes),
            forcing: forcing.clone(),
            tau: tau_bits,
            flow,
        };
        if flights.len() < REMEMBERED_FLIGHTS {
            flights.push(entry);
        } else {
            flights[*next] = entry;
        }
        *next = (*next + 1) % REMEMBERED_FLIGHTS;
        flow
    })
}

thread_local! {
    /// The last modal decomposition made on this thread: a boundary curve builds its unit
    /// afresh at every parameter value, but the gap and the restitution leave `A` unchanged.
    static LAST_MODES: std::cell::RefCell<Option<Arc<UnitModes>>> =
        const { std::cell::RefCell::new(None) };
}

/// The modal decomposition and forcing for `augmented` when it is the unit's (`D` = 6, of the
/// structure `[[A, B], [0, ωJ]]`); `None` elsewhere and where `A` has no well-conditioned
/// eigenbasis (the flights then take Padé's exponential).
pub(super) fn unit_modes<D: Dim>(
    augmented: &OMatrix<f64, D, D>,
) -> Option<(Arc<UnitModes>, ModalForcing)>
where
    DefaultAllocator: Allocator<D, D>,
{
    if D::try_to_usize() != Some(UNIT_SIZE) {
        return None;
    }
    let unit = to_unit(augmented);
    let cached = LAST_MODES.with(|last| last.borrow().clone().filter(|m| m.fits(&unit)));
    let modes = match cached {
        Some(m) => m,
        None => {
            let system: Matrix4<f64> = unit.fixed_view::<4, 4>(0, 0).into_owned();
            let m = Arc::new(UnitModes::new(&system).filter(|m| m.fits(&unit))?);
            LAST_MODES.with(|last| *last.borrow_mut() = Some(Arc::clone(&m)));
            m
        }
    };
    let forcing = modes.forcing(&unit);
    Some((modes, forcing))
}

/// `exp(m)` of the unit's doubled stack matrix (outside the generic impl, as
/// [`dynamic_exp`]).
pub(super) fn unit_exp(
    m: &SMatrix<f64, { 2 * UNIT_SIZE }, { 2 * UNIT_SIZE }>,
) -> SMatrix<f64, { 2 * UNIT_SIZE }, { 2 * UNIT_SIZE }> {
    m.exp()
}

/// `exp(m)` of a heap matrix (outside the generic impl, whose bounds hide the method).
pub(super) fn dynamic_exp(m: &DMatrix<f64>) -> DMatrix<f64> {
    m.exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cycle_equations::{CycleEquations, ImpactCondition};

    /// The modal evaluation without memory (its flights two at a time, `flow_pair`) equals
    /// the one with its flights remembered (one at a time, [`remembered_flow`]), bit for bit:
    /// evaluations that share some flights and not others, of a cycle whose flights include
    /// equal and short ones (taken by the series).
    #[test]
    fn remembered_flights_change_no_bit() {
        use crate::test_models::{damped_paper_unit, paper_stops};
        use nalgebra::{Vector2, U6};
        let (unit, stops) = (damped_paper_unit(), paper_stops());
        let omega = 1.7;
        let mut g_hat = Matrix6::identity();
        g_hat
            .fixed_view_mut::<2, 2>(2, 2)
            .copy_from(&stops.impact_map(&unit));
        let contact = crate::flow::join(
            &nalgebra::Vector4::new(-1.0, 1.0, 0.0, 0.0),
            &Vector2::zeros(),
        );
        let impacts = [1.0, 1.0, -1.0, -1.0, 1.0]
            .iter()
            .map(|&s| ImpactCondition::<U6> {
                impact_map: g_hat,
                contact,
                stop: s * stops.gap,
            })
            .collect();
        let plain = CycleEquations::new(
            omega,
            unit.augmented_matrix(omega),
            impacts,
            vec![0],
            std::f64::consts::TAU / omega,
        )
        .with_modal_flow();
        let remembered = plain.clone().with_remembered_flights();
        let points = [
            [0.3, 0.2, 0.4, 0.6, 0.8],
            [0.3, 0.2, 0.4, 0.6, 0.8],
            [0.3, 0.2, 0.41, 0.6, 0.8],
            [0.5, 0.001, 0.002, 0.5, 0.501],
            [0.5, 0.001, 0.002, 0.5, 0.502],
            [0.1, 0.25, 0.5, 0.75, 0.999],
        ];
        for x in &points {
            let (a, b) = (
                plain.evaluate_with(x, true),
                remembered.evaluate_with(x, true),
            );
            let (Some(a), Some(b)) = (a, b) else {
                panic!("both evaluate at {x:?}");
            };
            for (fa, fb) in a.flights.iter().zip(&b.flights) {
                for (u, v) in fa.iter().zip(fb.iter()) {
                    assert_eq!(u.to_bits(), v.to_bits(), "{x:?}");
                }
            }
            for (u, v) in a.jacobian.iter().zip(b.jacobian.iter()) {
                assert_eq!(u.to_bits(), v.to_bits(), "{x:?}");
            }
        }
    }

    /// [`product`] of the unit's stack matrices (four wide with AVX) and its two-wide form
    /// equal nalgebra's product bit for bit, on matrices with entries of every sign and scale
    /// (and exact zeros, as the flows' phase rows hold).
    #[test]
    fn unit_product_is_nalgebras_bit_for_bit() {
        let mut next = crate::cycle::awkward_entries(0x9E37_79B9_7F4A_7C15);
        for _ in 0..20_000 {
            let a = Matrix6::from_fn(|_, _| next());
            let b = Matrix6::from_fn(|_, _| next());
            let fast = product(&a, &b);
            let slow = a * b;
            let x: &[f64; 36] = a.as_slice().try_into().expect("6 × 6");
            let y: &[f64; 36] = b.as_slice().try_into().expect("6 × 6");
            // The form without AVX, which the dispatch of `product` skips on this machine.
            let mut lanes = [0.0; 36];
            unit_product_lanes(x, y, &mut lanes);
            for ((x, y), z) in fast.iter().zip(slow.iter()).zip(lanes.iter()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{a} {b}");
                assert_eq!(z.to_bits(), y.to_bits(), "{a} {b}");
            }
        }
    }
}
