//! Impact sequences of a model with several contact pairs: the time-ordered list of
//! `(pair, side)` impacts over one least period of `p` forcing periods.
//!
//! For one pair this is a [`Signature`] (`ImpactSequence::from_signature`). For several pairs
//! each impact names its pair. Text form: whitespace-separated tokens `<pair><side>`, the pair
//! index from 0 and the side `+` (side 1) or `-` (side 2), e.g. `"0+ 1+ 0- 1-"`; a text
//! without pair indices (`"+-"`) is a signature of pair 0. Canonical form: the rotation whose
//! list of `(pair, side)` is smallest in lexicographic order, pairs ascending and `+` before
//! `-` (for one pair, the canonical form of [`Signature`]).
//!
//! On a compliant pair ([`crate::Compliance`]) an impact is a *contact phase*: the pair enters
//! its stop, stays in it under the contact's spring and dashpot, and leaves it. Its token ends
//! in `c` (`"0+c 0-c"`, `"0+c 1-"`). On a rigid pair of restitution 0 an impact may be a
//! *sticking phase*, token ending in `s` (`"0+s"`): the pair lands (`ṙ⁺ = 0`), is held on its
//! stop by the constrained flow and is released where the stop's force changes sign. The kinds
//! order rigid impact, contact, sticking for the same pair and side. In the cycle equations a
//! contact phase is two events, its entry and its exit, and a sticking phase two, its landing
//! impact and its release ([`ImpactSequence::events`]).

use std::fmt;
use thiserror::Error;

use crate::model::LinearModel;
use crate::signature::{
    Signature, SignatureError, MAX_CYCLE_IMPACTS, MAX_CYCLE_PERIOD, MAX_PERIOD,
};

/// Largest number of impacts in a sequence: a chain of 16 cells with the `++--` signature in
/// each (64 impacts) is the largest chain orbit this workbench is to study.
pub const MAX_SEQUENCE_IMPACTS: usize = 64;

/// An impact sequence that cannot be used, with the field it came from.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum SequenceError {
    /// The sequence is empty, holds a bad side or character, or the period is out of range.
    #[error(transparent)]
    Signature(#[from] SignatureError),
    /// A token is not `<pair><side>`.
    #[error("--signature token {token:?} is not a pair index followed by '+' or '-'")]
    BadToken {
        /// The rejected token.
        token: String,
    },
    /// The sequence has more impacts than [`MAX_SEQUENCE_IMPACTS`].
    #[error("--signature has {impacts} impacts: at most {max} are allowed")]
    TooManyImpacts {
        /// Number of impacts given.
        impacts: usize,
        /// The cap, [`MAX_SEQUENCE_IMPACTS`].
        max: usize,
    },
    /// An impact names a side of a pair that has no stop (a one-sided pair).
    #[error("--signature names side {side} of pair {pair}, which has no stop on that side")]
    NoStop {
        /// The pair.
        pair: usize,
        /// The side without a stop: `+` or `-`.
        side: char,
    },
    /// A contact phase (`<pair><side>c`) names a rigid pair: its impacts are written
    /// `<pair><side>`.
    #[error(
        "--signature has a contact phase on pair {pair}, which is rigid: write its impacts \
         without 'c'"
    )]
    ContactOnRigid {
        /// The rigid pair.
        pair: usize,
    },
    /// A rigid impact (`<pair><side>`) names a compliant pair: its impacts are contact
    /// phases, written `<pair><side>c`.
    #[error(
        "--signature has a rigid impact on pair {pair}, which is compliant: write its contact \
         phases with 'c' (e.g. '{pair}+c')"
    )]
    ImpactOnCompliant {
        /// The compliant pair.
        pair: usize,
    },
    /// A sequence with contact phases given to continuation or boundary following, whose
    /// events (grazing, vanishing impact) and test functions are those of rigid impacts.
    #[error(
        "--signature has contact phases ('c'): continuation and boundary following take rigid \
         impacts only"
    )]
    ContinuedContact,
    /// A sticking phase (`<pair><side>s`) names a pair that is compliant or whose
    /// restitution is not 0: only a rigid pair that lands without rebound sticks.
    #[error(
        "--signature has a sticking phase on pair {pair}, which is not a rigid pair of \
         restitution 0"
    )]
    StickWithRebound {
        /// The pair.
        pair: usize,
    },
    /// An impact names a pair the model does not have.
    #[error("--signature names pair {pair}: the model has pairs 0..{pairs}")]
    Pair {
        /// The rejected pair index.
        pair: usize,
        /// Number of pairs of the model.
        pairs: usize,
    },
}

/// What an impact of a sequence is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum ImpactKind {
    /// A rigid impact (`0+`): the velocities jump by the pair's impact map.
    #[default]
    Rigid,
    /// A contact phase of a compliant pair (`0+c`): entry and exit at the stop, the contact
    /// flow between.
    Contact,
    /// A sticking phase of a rigid pair of restitution 0 (`0+s`): the landing impact, the
    /// flow held on the stop, the release where the stop's force vanishes.
    Stick,
}

impl ImpactKind {
    /// The token's suffix: none, `c` or `s`.
    fn suffix(self) -> &'static str {
        match self {
            Self::Rigid => "",
            Self::Contact => "c",
            Self::Stick => "s",
        }
    }
}

/// One impact of a sequence: which pair hits which of its stops, and what kind of impact it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PairImpact {
    /// Index of the contact pair in [`LinearModel::pairs`].
    pub pair: usize,
    /// `+1` for side 1 (`r = +gap_side1`), `−1` for side 2 (`r = −gap_side2`).
    pub side: i8,
    /// A rigid impact (`0+`), a contact phase (`0+c`) or a sticking phase (`0+s`).
    pub kind: ImpactKind,
}

/// What an event of the cycle equations is: a rigid impact, or the entry into or the exit from
/// a contact phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum EventKind {
    /// A rigid impact: the velocities jump by the impact map.
    Impact,
    /// The pair reaches its stop and the contact flow begins (the state is continuous).
    Entry,
    /// The pair's penetration returns to 0 and free flight begins (the state is continuous).
    Exit,
    /// The force that holds a sticking pair on its stop vanishes and free flight begins (the
    /// state is continuous).
    Release,
}

impl PairImpact {
    /// A rigid impact of `pair` on side `side`.
    pub fn rigid(pair: usize, side: i8) -> Self {
        Self {
            pair,
            side,
            kind: ImpactKind::Rigid,
        }
    }

    /// A contact phase of the compliant `pair` on side `side`.
    pub fn compliant(pair: usize, side: i8) -> Self {
        Self {
            pair,
            side,
            kind: ImpactKind::Contact,
        }
    }

    /// A sticking phase of the rigid `pair` of restitution 0 on side `side`.
    pub fn sticking(pair: usize, side: i8) -> Self {
        Self {
            pair,
            side,
            kind: ImpactKind::Stick,
        }
    }

    /// Order key: pair ascending, then `+` before `-`, then the kind (rigid, contact, stick).
    fn key(self) -> (usize, u8, ImpactKind) {
        (self.pair, u8::from(self.side != 1), self.kind)
    }
}

/// The impacts of all pairs over one cycle of `period` forcing periods, in time order and
/// canonical rotation.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ImpactSequence {
    impacts: Vec<PairImpact>,
    period: u32,
}

impl ImpactSequence {
    /// The sequence of time-ordered impacts over `period` forcing periods, rotated to
    /// canonical form, with the caps of the multi-start search.
    ///
    /// # Errors
    /// [`SequenceError::Signature`] for an empty list, a side other than `±1` or a period
    /// outside `1..=MAX_PERIOD`; [`SequenceError::TooManyImpacts`] above
    /// [`MAX_SEQUENCE_IMPACTS`].
    pub fn new(impacts: &[PairImpact], period: u32) -> Result<Self, SequenceError> {
        Self::with_caps(impacts, period, MAX_SEQUENCE_IMPACTS, MAX_PERIOD)
    }

    /// The sequence of the impacts of a simulated cycle over `period` forcing periods, to be
    /// solved from the cycle's own impact phases: up to
    /// [`MAX_CYCLE_IMPACTS`] impacts and [`MAX_CYCLE_PERIOD`] periods, as
    /// [`Signature::from_cycle`].
    ///
    /// # Errors
    /// As [`ImpactSequence::new`], with those caps.
    pub fn from_cycle(impacts: &[PairImpact], period: u32) -> Result<Self, SequenceError> {
        Self::with_caps(impacts, period, MAX_CYCLE_IMPACTS, MAX_CYCLE_PERIOD)
    }

    fn with_caps(
        impacts: &[PairImpact],
        period: u32,
        max_impacts: usize,
        max_period: u32,
    ) -> Result<Self, SequenceError> {
        if impacts.is_empty() {
            return Err(SignatureError::Empty.into());
        }
        if let Some(bad) = impacts.iter().find(|i| i.side != 1 && i.side != -1) {
            return Err(SignatureError::BadSide { side: bad.side }.into());
        }
        if impacts.len() > max_impacts {
            return Err(SequenceError::TooManyImpacts {
                impacts: impacts.len(),
                max: max_impacts,
            });
        }
        if period == 0 || period > max_period {
            return Err(SignatureError::Period {
                period,
                max: max_period,
            }
            .into());
        }
        let n = impacts.len();
        let keys: Vec<(usize, u8, ImpactKind)> = impacts.iter().map(|i| i.key()).collect();
        let keys = &keys;
        let rotation = move |s: usize| (0..n).map(move |k| keys[(k + s) % n]);
        let shift = (1..n).fold(0, |best, s| {
            if rotation(s).lt(rotation(best)) {
                s
            } else {
                best
            }
        });
        Ok(Self {
            impacts: (0..n).map(|k| impacts[(k + shift) % n]).collect(),
            period,
        })
    }

    /// The sequence of a one-pair signature: every impact on pair 0.
    pub fn from_signature(signature: &Signature) -> Self {
        Self {
            impacts: signature
                .sides()
                .iter()
                .map(|&side| PairImpact::rigid(0, side))
                .collect(),
            period: signature.period(),
        }
    }

    /// Parses the text form (see the module docs) with its period.
    ///
    /// # Errors
    /// As [`Signature::parse`] for a text without pair indices; otherwise
    /// [`SequenceError::BadToken`] for a token that is not `<pair><side>`, and as
    /// [`ImpactSequence::new`].
    pub fn parse(text: &str, period: u32) -> Result<Self, SequenceError> {
        let text = text.trim();
        if !text.chars().any(|c| c.is_ascii_digit()) {
            return Ok(Self::from_signature(&Signature::parse(text, period)?));
        }
        let impacts = text
            .split_whitespace()
            .map(|token| {
                let bad = || SequenceError::BadToken {
                    token: token.to_string(),
                };
                let (body, kind) = if let Some(body) = token.strip_suffix('c') {
                    (body, ImpactKind::Contact)
                } else if let Some(body) = token.strip_suffix('s') {
                    (body, ImpactKind::Stick)
                } else {
                    (token, ImpactKind::Rigid)
                };
                let (pair, side) = body.split_at(body.len().saturating_sub(1));
                let side = match side {
                    "+" => 1,
                    "-" => -1,
                    _ => return Err(bad()),
                };
                let pair = pair.parse::<usize>().map_err(|_| bad())?;
                Ok(PairImpact { pair, side, kind })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::new(&impacts, period)
    }

    /// The impacts in canonical order.
    pub fn impacts(&self) -> &[PairImpact] {
        &self.impacts
    }

    /// Whether some impact is a contact or a sticking phase.
    pub fn has_contact_phases(&self) -> bool {
        self.impacts.iter().any(|i| i.kind != ImpactKind::Rigid)
    }

    /// The events of the cycle equations in time order: one per rigid impact, two (entry,
    /// exit) per contact phase, two (landing impact, release) per sticking phase. Each
    /// event's unknown is its time; its condition that the pair's coordinate is at the stop
    /// (a release: that the stop's force is zero).
    pub(crate) fn events(&self) -> Vec<(PairImpact, EventKind)> {
        self.impacts
            .iter()
            .flat_map(|&i| {
                let kinds: &[EventKind] = match i.kind {
                    ImpactKind::Rigid => &[EventKind::Impact],
                    ImpactKind::Contact => &[EventKind::Entry, EventKind::Exit],
                    ImpactKind::Stick => &[EventKind::Impact, EventKind::Release],
                };
                kinds.iter().map(move |&k| (i, k))
            })
            .collect()
    }

    /// Number of forcing periods in the cycle.
    pub fn period(&self) -> u32 {
        self.period
    }

    /// The one-pair signature of this sequence when every impact is on pair 0.
    pub fn as_signature(&self) -> Option<Signature> {
        if self.impacts.iter().all(|i| i.pair == 0) {
            let sides: Vec<i8> = self.impacts.iter().map(|i| i.side).collect();
            Signature::from_cycle(&sides, self.period).ok()
        } else {
            None
        }
    }

    /// The signature of pair `pair` alone (its own impacts in time order, canonical), or
    /// `None` if that pair does not impact in this cycle.
    pub fn pair_signature(&self, pair: usize) -> Option<Signature> {
        let sides: Vec<i8> = self
            .impacts
            .iter()
            .filter(|i| i.pair == pair)
            .map(|i| i.side)
            .collect();
        Signature::from_cycle(&sides, self.period).ok()
    }

    /// Checks that every impact names a pair of `model`, on a side that has a stop, with the
    /// pair's contact law (a contact phase on a compliant pair, a rigid impact on a rigid one).
    ///
    /// # Errors
    /// [`SequenceError::Pair`] for the first impact on a pair the model lacks;
    /// [`SequenceError::NoStop`] for the first impact on a side without a stop;
    /// [`SequenceError::ContactOnRigid`] or [`SequenceError::ImpactOnCompliant`] for the first
    /// impact whose kind is not its pair's; [`SequenceError::StickWithRebound`] for a sticking
    /// phase on a pair that is compliant or has a restitution other than 0.
    pub fn check(&self, model: &LinearModel) -> Result<(), SequenceError> {
        let pairs = model.pairs();
        if let Some(bad) = self.impacts.iter().find(|i| i.pair >= pairs.len()) {
            return Err(SequenceError::Pair {
                pair: bad.pair,
                pairs: pairs.len(),
            });
        }
        let absent = |i: &&PairImpact| {
            let pair = &pairs[i.pair];
            let gap = if i.side == 1 {
                pair.gap_side1
            } else {
                pair.gap_side2
            };
            !gap.is_finite()
        };
        if let Some(bad) = self.impacts.iter().find(absent) {
            return Err(SequenceError::NoStop {
                pair: bad.pair,
                side: if bad.side == 1 { '+' } else { '-' },
            });
        }
        let compliant = |i: &PairImpact| model.compliance(i.pair).is_some();
        for i in &self.impacts {
            match i.kind {
                ImpactKind::Contact if !compliant(i) => {
                    return Err(SequenceError::ContactOnRigid { pair: i.pair })
                }
                ImpactKind::Rigid if compliant(i) => {
                    return Err(SequenceError::ImpactOnCompliant { pair: i.pair })
                }
                ImpactKind::Stick if compliant(i) || pairs[i.pair].restitution != 0.0 => {
                    return Err(SequenceError::StickWithRebound { pair: i.pair })
                }
                _ => {}
            }
        }
        Ok(())
    }
}

impl fmt::Display for ImpactSequence {
    /// The text form: `0+ 1+ 0- 1-`, a contact phase with a trailing `c` (`0+c`), a sticking
    /// phase with a trailing `s` (`0+s`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, i) in self.impacts.iter().enumerate() {
            if k > 0 {
                f.write_str(" ")?;
            }
            write!(f, "{}{}", i.pair, if i.side == 1 { '+' } else { '-' })?;
            f.write_str(i.kind.suffix())?;
        }
        Ok(())
    }
}
