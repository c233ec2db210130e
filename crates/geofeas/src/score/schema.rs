//! The options of the scores as a user gives them, defined once: name, default, kind, allowed
//! values, meaning and the scores that take each, in the order of [`Options`]' fields.
//!
//! The score functions of `geofeas.scores` (their keyword defaults are checked against it), the
//! options the association passes to its score, the flags of `geofeas score` and the score
//! options table of `README.md` are derived from [`options`] or checked against it by a test
//! (`tests/test_score_schema.py`); the defaults are read from [`Options::default`] (the test
//! below). Adding a score option: a field of [`Options`] with its default, its use in
//! [`super::Score::from_name`], a row here, its kernel and its tests.

use super::monte_carlo::Sampler;
use super::spec::{Options, METHOD_NAMES, SCORE_NAMES};
use super::{MonteCarlo, Polygon};

/// A default value, typed as the user gives it (its variant is the option's kind).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(u64),
    Text(String),
}

impl Value {
    /// The kind of the option: `"bool"`, `"int"` or `"text"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Bool(_) => "bool",
            Self::Int(_) => "int",
            Self::Text(_) => "text",
        }
    }
}

/// One option of the scores.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionSpec {
    /// Keyword name (`--name` on the command line).
    pub name: &'static str,
    /// Default, from [`Options::default`].
    pub default: Value,
    /// The allowed values of a text option (empty: any value).
    pub choices: Vec<&'static str>,
    /// The allowed range `[min, max]` of an integer option (`None`: any `u64`).
    pub range: Option<(u64, u64)>,
    /// Meaning, with the unit.
    pub help: &'static str,
    /// The scores (of [`SCORE_NAMES`]) that take the option; the others refuse it.
    pub scores: Vec<&'static str>,
}

/// The names of the scores ([`SCORE_NAMES`], the names [`super::Score::from_name`] accepts).
pub fn score_names() -> Vec<&'static str> {
    SCORE_NAMES.to_vec()
}

/// The options of the scores, in the order of [`Options`]' fields.
pub fn options() -> Vec<OptionSpec> {
    let d = Options::default();
    let spec = |name, default, help, scores: &[&'static str]| OptionSpec {
        name,
        default,
        choices: Vec::new(),
        range: None,
        help,
        scores: scores.to_vec(),
    };
    vec![
        spec(
            "threshold",
            Value::Bool(d.threshold),
            "exactly 0 for disjoint and 1 for nested ellipses (constraints 46-48), the GLR between",
            &["glr"],
        ),
        OptionSpec {
            choices: METHOD_NAMES.to_vec(),
            ..spec(
                "method",
                Value::Text(d.method),
                "overlap computed analytically (exact) or on equal-area polygons (polygon)",
                &["overlap"],
            )
        },
        OptionSpec {
            range: Some((Polygon::MIN_VERTICES as u64, Polygon::MAX_VERTICES as u64)),
            ..spec(
                "vertices",
                Value::Int(d.vertices as u64),
                "vertices of each ellipse's polygon, with method polygon",
                &["overlap"],
            )
        },
        OptionSpec {
            range: Some((1, MonteCarlo::MAX_SAMPLES as u64)),
            ..spec(
                "samples",
                Value::Int(d.samples as u64),
                "Monte-Carlo samples per pair",
                &["monte_carlo"],
            )
        },
        spec(
            "seed",
            Value::Int(d.seed),
            "seed of the Monte-Carlo random streams: pair k draws from the stream of (seed, k)",
            &["monte_carlo"],
        ),
        OptionSpec {
            choices: Sampler::NAMES.to_vec(),
            ..spec(
                "sampler",
                Value::Text(d.sampler),
                "Monte-Carlo sampler: the Gaussian of the smaller ellipse weighted by 1/p (eq. 55), \
                 uniform in it, or scrambled Sobol points in it",
                &["monte_carlo"],
            )
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::super::Score;
    use super::*;

    /// Reads the options back into [`Options`]; a default that drifts from
    /// [`Options::default`] fails here, and so does a choice or a bound the scores refuse.
    #[test]
    fn defaults_are_those_of_the_engine() {
        let o = options();
        let mut read = Options {
            threshold: true,
            method: String::new(),
            vertices: 0,
            samples: 0,
            seed: 1,
            sampler: String::new(),
        };
        for s in &o {
            match (s.name, &s.default) {
                ("threshold", Value::Bool(v)) => read.threshold = *v,
                ("method", Value::Text(v)) => read.method = v.clone(),
                ("vertices", Value::Int(v)) => read.vertices = *v as usize,
                ("samples", Value::Int(v)) => read.samples = *v as usize,
                ("seed", Value::Int(v)) => read.seed = *v,
                ("sampler", Value::Text(v)) => read.sampler = v.clone(),
                (name, v) => panic!("{name}: unexpected option or kind {v:?}"),
            }
        }
        assert_eq!(read, Options::default());
        // every name once
        let mut names: Vec<&str> = o.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), o.len());
        // every score name parses, and takes the options listed for it
        for name in score_names() {
            assert!(
                Score::from_name(name, &Options::default()).is_ok(),
                "{name}"
            );
        }
        for s in &o {
            assert!(!s.scores.is_empty(), "{}", s.name);
            for score in &s.scores {
                assert!(score_names().contains(score), "{}: {score}", s.name);
            }
            if let Value::Text(default) = &s.default {
                assert!(s.choices.contains(&default.as_str()), "{}", s.name);
            }
        }
        // every choice and both ends of every range are accepted, one beyond them refused
        let with = |name: &str, value: Value| {
            let mut opts = Options {
                method: "polygon".into(),
                ..Options::default()
            };
            match (name, value) {
                ("method", Value::Text(v)) => opts.method = v,
                ("vertices", Value::Int(v)) => opts.vertices = v as usize,
                ("samples", Value::Int(v)) => opts.samples = v as usize,
                ("sampler", Value::Text(v)) => opts.sampler = v,
                (name, v) => panic!("{name}: {v:?}"),
            }
            let score = if name == "method" || name == "vertices" {
                "overlap"
            } else {
                "monte_carlo"
            };
            Score::from_name(score, &opts)
        };
        for s in &o {
            for c in &s.choices {
                assert!(with(s.name, Value::Text((*c).into())).is_ok(), "{c}");
            }
            if !s.choices.is_empty() {
                assert!(
                    with(s.name, Value::Text("nope".into())).is_err(),
                    "{}",
                    s.name
                );
            }
            if let Some((lo, hi)) = s.range {
                assert!(with(s.name, Value::Int(lo)).is_ok(), "{}", s.name);
                assert!(with(s.name, Value::Int(hi)).is_ok(), "{}", s.name);
                assert!(with(s.name, Value::Int(lo - 1)).is_err(), "{}", s.name);
                assert!(with(s.name, Value::Int(hi + 1)).is_err(), "{}", s.name);
            }
        }
    }
}
