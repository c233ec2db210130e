//! A score chosen by name at run time, for callers that pick scores from configuration (the
//! Python bindings, the CLI, the track pipeline).
//!
//! [`Score`] wraps every [`PairScore`] of the crate and dispatches the shared drivers to it, so
//! a new score needs one enum variant and one line per match here.

use super::monte_carlo::Sampler;
use super::{
    score_cdist, score_pairs, Exact, GaussianScore, Glr, Interrupt, MonteCarlo, PairScore, Polygon,
};
use crate::ellipse::Ellipse;
use crate::error::{Error, Result};

/// Options of every score; each score reads the ones it uses.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// GLR: force 0 / 1 for disjoint / nested ellipses.
    pub threshold: bool,
    /// Overlap: the method (`"exact"` or `"polygon"`).
    pub method: String,
    /// Polygon overlap: vertices per ellipse.
    pub vertices: usize,
    /// Monte-Carlo: samples per pair.
    pub samples: usize,
    /// Monte-Carlo: seed of the random streams.
    pub seed: u64,
    /// Monte-Carlo: the sampler (`"importance"`, `"uniform"` or `"sobol"`).
    pub sampler: String,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            threshold: false,
            method: "exact".into(),
            vertices: Polygon::DEFAULT_VERTICES,
            samples: MonteCarlo::default().samples,
            seed: 0,
            sampler: "importance".into(),
        }
    }
}

/// Names accepted by [`Score::from_name`].
pub const SCORE_NAMES: [&str; 6] = [
    "glr",
    "overlap",
    "monte_carlo",
    "bhattacharyya",
    "hellinger",
    "gaussian_product",
];

/// Methods of the `"overlap"` score ([`Options::method`]): the analytic intersection or the
/// equal-area polygons.
pub const METHOD_NAMES: [&str; 2] = ["exact", "polygon"];

/// One of the crate's scores, chosen at run time.
#[derive(Debug, Clone, PartialEq)]
pub enum Score {
    Glr(Glr),
    Polygon(Polygon),
    MonteCarlo(MonteCarlo),
    Exact(Exact),
    Gaussian(GaussianScore),
}

impl Score {
    /// The score called `name` (one of [`SCORE_NAMES`]) with `options`, validated.
    pub fn from_name(name: &str, options: &Options) -> Result<Self> {
        match name {
            "glr" => Ok(Self::Glr(Glr {
                threshold: options.threshold,
            })),
            "overlap" => match options.method.as_str() {
                "polygon" => {
                    if !(Polygon::MIN_VERTICES..=Polygon::MAX_VERTICES).contains(&options.vertices)
                    {
                        return Err(Error::InvalidOption {
                            name: "vertices",
                            reason: format!(
                                "must be in [{}, {}], got {}",
                                Polygon::MIN_VERTICES,
                                Polygon::MAX_VERTICES,
                                options.vertices
                            ),
                        });
                    }
                    Ok(Self::Polygon(Polygon::new(options.vertices)))
                }
                "exact" => Ok(Self::Exact(Exact)),
                other => Err(Error::InvalidOption {
                    name: "method",
                    reason: format!(
                        "unknown overlap method '{other}' (expected one of {METHOD_NAMES:?})"
                    ),
                }),
            },
            "monte_carlo" => {
                if !(1..=MonteCarlo::MAX_SAMPLES).contains(&options.samples) {
                    return Err(Error::InvalidOption {
                        name: "samples",
                        reason: format!(
                            "must be in [1, {}], got {}",
                            MonteCarlo::MAX_SAMPLES,
                            options.samples
                        ),
                    });
                }
                let sampler =
                    Sampler::from_name(&options.sampler).ok_or_else(|| Error::InvalidOption {
                        name: "sampler",
                        reason: format!(
                            "unknown sampler '{}' (expected one of {:?})",
                            options.sampler,
                            Sampler::NAMES
                        ),
                    })?;
                Ok(Self::MonteCarlo(MonteCarlo {
                    samples: options.samples,
                    seed: options.seed,
                    sampler,
                }))
            }
            "bhattacharyya" => Ok(Self::Gaussian(GaussianScore::Bhattacharyya)),
            "hellinger" => Ok(Self::Gaussian(GaussianScore::Hellinger)),
            "gaussian_product" => Ok(Self::Gaussian(GaussianScore::Product)),
            other => Err(Error::InvalidOption {
                name: "score",
                reason: format!("unknown score '{other}' (expected one of {SCORE_NAMES:?})"),
            }),
        }
    }

    /// Elementwise scores (see [`score_pairs`]).
    pub fn pairs(
        &self,
        a: &[Ellipse],
        b: &[Ellipse],
        out: &mut [f64],
        interrupt: Interrupt<'_>,
    ) -> Result<()> {
        match self {
            Self::Glr(s) => score_pairs(s, a, b, out, interrupt),
            Self::Polygon(s) => score_pairs(s, a, b, out, interrupt),
            Self::MonteCarlo(s) => score_pairs(s, a, b, out, interrupt),
            Self::Exact(s) => score_pairs(s, a, b, out, interrupt),
            Self::Gaussian(s) => score_pairs(s, a, b, out, interrupt),
        }
    }

    /// All-pairs scores (see [`score_cdist`]).
    pub fn cdist(
        &self,
        a: &[Ellipse],
        b: &[Ellipse],
        out: &mut [f64],
        interrupt: Interrupt<'_>,
    ) -> Result<()> {
        match self {
            Self::Glr(s) => score_cdist(s, a, b, out, interrupt),
            Self::Polygon(s) => score_cdist(s, a, b, out, interrupt),
            Self::MonteCarlo(s) => score_cdist(s, a, b, out, interrupt),
            Self::Exact(s) => score_cdist(s, a, b, out, interrupt),
            Self::Gaussian(s) => score_cdist(s, a, b, out, interrupt),
        }
    }

    /// The score of one valid pair; `index` selects the random stream of seeded scores.
    pub fn one(&self, a: &Ellipse, b: &Ellipse, index: u64) -> f64 {
        match self {
            Self::Glr(s) => s.score(&s.prepare(a), &s.prepare(b), index),
            Self::Polygon(s) => s.score(&s.prepare(a), &s.prepare(b), index),
            Self::MonteCarlo(s) => s.score(&s.prepare(a), &s.prepare(b), index),
            Self::Exact(s) => s.score(&s.prepare(a), &s.prepare(b), index),
            Self::Gaussian(s) => s.score(&s.prepare(a), &s.prepare(b), index),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_bad_options() {
        let o = Options::default();
        for name in SCORE_NAMES {
            assert!(Score::from_name(name, &o).is_ok());
        }
        assert!(Score::from_name("nope", &o).is_err());
        let bad = Options {
            vertices: 3,
            method: "polygon".into(),
            ..Options::default()
        };
        assert!(Score::from_name("overlap", &bad)
            .unwrap_err()
            .to_string()
            .contains("vertices"));
        let bad = Options {
            sampler: "halton".into(),
            ..Options::default()
        };
        assert!(Score::from_name("monte_carlo", &bad)
            .unwrap_err()
            .to_string()
            .contains("sampler"));
        assert_eq!(
            Score::from_name("overlap", &Options::default()).unwrap(),
            Score::Exact(Exact)
        );
    }
}
