//! JSON forms of the results. Non-finite numbers become `null`, never NaN or infinity.

use nalgebra::Vector4;
use rattle_analytic::{LinearResponse, Orbit, Violation};
use serde_json::{json, Value};

/// A number, or `null` when it is not finite.
pub fn number(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// A state `(u_o, u_i, u̇_o, u̇_i)` as an array.
pub fn state(x: &Vector4<f64>) -> Value {
    Value::Array(x.iter().map(|&v| number(v)).collect())
}

/// The linear steady state. `unbounded` says why amplitudes are `null` at undamped resonance;
/// `touches_stops` whether the linear motion would reach stops with gap `gap`.
pub fn linear(response: &LinearResponse, gap: Option<f64>) -> Value {
    json!({
        "outer_amplitude": number(response.outer_amplitude),
        "inner_amplitude": number(response.inner_amplitude),
        "relative_amplitude": number(response.relative_amplitude),
        "transmittance_db": number(response.transmittance_db),
        "unbounded": response.unbounded,
        "touches_stops": gap.map(|g| response.relative_amplitude > g),
    })
}

/// One violation, e.g. `{"kind": "penetration", "side": 2, "time": 1.3, "excess": 0.02}`.
pub fn violation(v: &Violation) -> Value {
    match *v {
        Violation::Penetration { side, time, excess } => json!({
            "kind": "penetration", "side": side.number(), "time": number(time), "excess": number(excess),
        }),
        Violation::WrongApproach {
            side,
            relative_velocity,
        } => json!({
            "kind": "wrong_approach", "side": side.number(), "relative_velocity": number(relative_velocity),
        }),
    }
}

/// One two-impact orbit.
pub fn orbit(o: &Orbit, branch: usize) -> Value {
    json!({
        "beta": number(o.beta),
        "branch": branch,
        "gap": number(o.gap),
        "alpha": number(o.alpha),
        "state_before_impact": state(&o.state_before_impact),
        "state_after_impact": state(&o.state_after_impact),
        "state_before_side2": state(&o.state_before_side2),
        "outer_amplitude": number(o.outer_amplitude),
        "transmittance_db": number(o.transmittance_db),
        "viable": o.viable,
        "violations": o.violations.iter().map(violation).collect::<Vec<_>>(),
        "floquet_multipliers": o.floquet_multipliers.iter().map(|m| json!([number(m.re), number(m.im)])).collect::<Vec<_>>(),
        "stable": o.stable,
    })
}

/// One CSV row from JSON values: `null` as an empty cell, strings quoted (quotes doubled),
/// numbers and booleans as JSON writes them; cells joined by commas, no line end.
pub fn csv_row(row: Vec<Value>) -> String {
    row.into_iter()
        .map(|v| match v {
            Value::Null => String::new(),
            Value::String(s) => format!("\"{}\"", s.replace('"', "\"\"")),
            other => other.to_string(),
        })
        .collect::<Vec<_>>()
        .join(",")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_numbers_are_null() {
        assert_eq!(number(f64::NAN), Value::Null);
        assert_eq!(number(f64::INFINITY), Value::Null);
        assert_eq!(number(1.5), json!(1.5));
    }
}
