//! The options of [`super::associate`] as a user gives them, defined once: name, default,
//! allowed values and meaning, in the order of `geofeas.associate`'s signature.
//!
//! The Python function's keyword arguments, `geofeas.ASSOCIATION_DEFAULTS`, the flags of
//! `geofeas associate` and the options table of `docs/association.md` are derived from
//! [`options`] or checked against it by a test (`tests/test_options_schema.py`); the defaults
//! are those of [`super::Options::default`] (the test below). Adding an option: a field of
//! [`super::Options`] with its default, a row here, its kernel and its tests.

use super::combine::COMBINE_NAMES;
use super::evidence::Model;
use super::Options;
use crate::score::spec::SCORE_NAMES;

/// A default value, typed as the user gives it.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Float(f64),
    Int(u64),
    Bool(bool),
    Text(&'static str),
}

/// One option of the association.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionSpec {
    /// Keyword name (`--name-with-dashes` on the command line).
    pub name: &'static str,
    /// Default.
    pub default: Value,
    /// The allowed values of a text option (empty: any value its check accepts).
    pub choices: Vec<&'static str>,
    /// Meaning, with the unit.
    pub help: &'static str,
}

/// Score names the association accepts: the core's scores and `glr_threshold`, the GLR with
/// `threshold = true`.
pub fn score_names() -> Vec<&'static str> {
    let mut out = vec!["glr", "glr_threshold"];
    out.extend(SCORE_NAMES.iter().copied().filter(|s| *s != "glr"));
    out
}

/// The options of the association, in signature order.
pub fn options() -> Vec<OptionSpec> {
    let d = Options::default();
    let spec = |name, default, help| OptionSpec {
        name,
        default,
        choices: Vec::new(),
        help,
    };
    // the default score by name (the test below holds it equal to `Options::default().score`)
    let score = "glr";
    vec![
        OptionSpec {
            choices: score_names(),
            ..spec(
                "score",
                Value::Text(score),
                "per-instant geofeasibility score of the score column (the classes come from the \
             posterior)",
            )
        },
        OptionSpec {
            choices: COMBINE_NAMES.to_vec(),
            ..spec(
                "combine",
                Value::Text(d.combine.name()),
                "how the per-instant scores become the score column",
            )
        },
        spec(
            "p_match",
            Value::Float(d.p_match),
            "class match when p_same >= this (the automatic-merge error rate accepted)",
        ),
        spec(
            "p_reject",
            Value::Float(d.p_reject),
            "class non-match when p_same <= this (the rate of true pairs dropped accepted)",
        ),
        spec(
            "max_gap",
            Value::Float(d.align.max_gap),
            "longest gap between two reports of a track that is interpolated (s)",
        ),
        spec(
            "horizon",
            Value::Float(d.align.horizon),
            "how far a track is extrapolated beyond its first / last report (s)",
        ),
        spec(
            "process_noise",
            Value::Float(d.align.process_noise),
            "diffusion q of the position around straight-line motion (m^2/s)",
        ),
        spec(
            "max_still_gap",
            Value::Float(d.align.max_still_gap),
            "longest gap interpolated across when the track stays still over it: its two \
             reports within the 99th percentile of the diffusion's spread (s)",
        ),
        spec(
            "same_source",
            Value::Bool(d.index.same_source),
            "also compare tracks of the same source",
        ),
        spec(
            "correlation_time",
            Value::Float(d.correlation_time),
            "error correlation time: k instants count as k_eff independent ones (s)",
        ),
        spec(
            "window",
            Value::Float(d.index.window),
            "longest time span of one chunk of the space-time index (s; speed only)",
        ),
        spec(
            "inflation",
            Value::Text("auto"),
            "covariance inflation: 'auto' (one factor per pair of sources, from the data) or a \
             number multiplying every covariance",
        ),
        spec(
            "completeness",
            Value::Float(d.model.completeness),
            "share of the picture's objects the most complete source holds a track of",
        ),
        spec(
            "false_tracks",
            Value::Float(Model::DEFAULT_FALSE_TRACKS),
            "share of each source's tracks that are false (Python: also {source: share})",
        ),
        spec(
            "density_cell",
            Value::Float(d.model.cell),
            "cell side of the picture's object-density grid (m)",
        ),
        spec(
            "exact_limit",
            Value::Int(d.inference.exact_limit as u64),
            "components with at most this many feasible partitions are enumerated exactly",
        ),
        spec(
            "chains",
            Value::Int(d.inference.chains as u64),
            "independent chains of the sampler of larger components",
        ),
        spec(
            "sweeps",
            Value::Int(d.inference.sweeps as u64),
            "sweeps per chain of the sampler",
        ),
        spec(
            "posterior_seed",
            Value::Int(d.inference.seed),
            "seed of the sampler",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads the options back into [`Options`] the way the bindings do; a default that drifts
    /// from [`Options::default`] fails here.
    #[test]
    fn defaults_are_those_of_the_engine() {
        let o = options();
        let get = |name: &str| o.iter().find(|s| s.name == name).unwrap().default.clone();
        let f = |name: &str| match get(name) {
            Value::Float(v) => v,
            other => panic!("{name}: {other:?}"),
        };
        let i = |name: &str| match get(name) {
            Value::Int(v) => v as usize,
            other => panic!("{name}: {other:?}"),
        };
        let d = Options::default();
        let Value::Text(score) = get("score") else {
            panic!("score is a name")
        };
        let by_name =
            crate::score::Score::from_name(score, &crate::score::spec::Options::default()).unwrap();
        assert_eq!(by_name, d.score);
        assert_eq!(f("p_match"), d.p_match);
        assert_eq!(f("p_reject"), d.p_reject);
        assert_eq!(f("max_gap"), d.align.max_gap);
        assert_eq!(f("horizon"), d.align.horizon);
        assert_eq!(f("process_noise"), d.align.process_noise);
        assert_eq!(f("correlation_time"), d.correlation_time);
        assert_eq!(f("window"), d.index.window);
        assert_eq!(f("completeness"), d.model.completeness);
        assert_eq!(f("density_cell"), d.model.cell);
        assert_eq!(get("same_source"), Value::Bool(d.index.same_source));
        assert_eq!(get("combine"), Value::Text(d.combine.name()));
        assert_eq!(get("inflation"), Value::Text("auto"));
        assert_eq!(d.inflation, None);
        assert_eq!(i("exact_limit"), d.inference.exact_limit);
        assert_eq!(i("chains"), d.inference.chains);
        assert_eq!(i("sweeps"), d.inference.sweeps);
        assert_eq!(i("posterior_seed") as u64, d.inference.seed);
        // every name once; every choice a name the engine reads
        let mut names: Vec<&str> = o.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), o.len());
        for c in &o.iter().find(|s| s.name == "combine").unwrap().choices {
            assert!(super::super::Combine::from_name(c).is_ok());
        }
        for s in score_names() {
            let base = if s == "glr_threshold" { "glr" } else { s };
            let opts = crate::score::spec::Options::default();
            assert!(crate::score::Score::from_name(base, &opts).is_ok(), "{s}");
        }
    }
}
