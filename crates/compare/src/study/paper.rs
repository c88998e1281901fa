//! The paper's claims and numbers (Banerjee, Das & Calius), in one place: what the figures mark
//! and the report checks.

/// Figure 5: the resonance peaks, rad/s.
pub const RESONANCE_PEAKS: [f64; 2] = [1.25, 2.45];

/// Figure 5: the anti-resonance valley, rad/s.
pub const ANTI_RESONANCE: f64 = 1.72;

/// The linear unit's attenuation bands, rad/s (`∞`: open above).
pub const LINEAR_BANDS: [(f64, f64); 2] = [(1.5, 2.2), (2.9, f64::INFINITY)];

/// The impacting unit's attenuation band, rad/s: "from 1.0 rad/s to ∞ with no transmission
/// band inside".
pub const IMPACTING_BAND: (f64, f64) = (1.0, f64::INFINITY);

/// Nigm and Shabana: the two-impact solution is non-viable for `0 ≤ β ≤` this.
pub const NON_VIABLE_BETA: f64 = 0.18;

/// Figure 2's frequencies, rad/s.
pub const FIGURE2_OMEGAS: [f64; 3] = [0.5, 1.0, 2.0];

/// Figure 4's frequencies, rad/s.
pub const FIGURE4_OMEGAS: [f64; 2] = [1.0, 2.0];

/// Frequencies at which the `β` family is explored, rad/s: below, inside and above the first
/// linear attenuation band.
pub const FAMILY_OMEGAS: [f64; 3] = [1.5, 2.0, 3.0];

/// How far a number read off the paper's plots may be from ours and still count as
/// reproduced: peaks and band edges are read to about 0.03–0.1 rad/s from the figure.
pub mod read_off {
    /// Resonance peaks, rad/s.
    pub const PEAK: f64 = 0.03;
    /// The anti-resonance valley, rad/s.
    pub const VALLEY: f64 = 0.02;
    /// A band's lower edge, rad/s.
    pub const BAND_START: f64 = 0.05;
    /// A band's upper edge, rad/s (the paper's 2.2 is drawn where the curve is steep).
    pub const BAND_END: f64 = 0.1;
    /// The Nigm–Shabana bound on `β`.
    pub const BETA: f64 = 0.02;
}

/// "Sides are 0.5 m apart" read as the clearance: the other reading halves the gap.
pub const READING_B_GAP_FACTOR: f64 = 0.5;

/// A claimed band `(from, to, label)`.
pub type ClaimedBand = (f64, f64, String);

/// A claimed peak or valley `(ω, label)`.
pub type ClaimedMark = (f64, String);

/// The claimed bands and marks drawn on the transmittance figure.
pub fn claims() -> (Vec<ClaimedBand>, Vec<ClaimedMark>) {
    let band = |(a, b): (f64, f64), what: &str| {
        let to = if b.is_infinite() {
            "∞".to_owned()
        } else {
            b.to_string()
        };
        (a, b, format!("paper: {what} band {a:.1}–{to}"))
    };
    (
        vec![
            band(LINEAR_BANDS[0], "linear"),
            band(LINEAR_BANDS[1], "linear"),
            band(IMPACTING_BAND, "impacting"),
        ],
        vec![
            (
                RESONANCE_PEAKS[0],
                format!("paper peak {}", RESONANCE_PEAKS[0]),
            ),
            (ANTI_RESONANCE, format!("paper valley {ANTI_RESONANCE}")),
            (
                RESONANCE_PEAKS[1],
                format!("paper peak {}", RESONANCE_PEAKS[1]),
            ),
        ],
    )
}
