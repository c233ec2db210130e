//! The option sets of the particle-filter tracker (seed 003, Table 1 defaults), each declared
//! once: [`PfOptions`], the bank of filters, shared by every entry point; [`PfRunOptions`] and
//! [`PfTrackOptions`], the rest of a simulated run and of tracking given frames; and
//! [`PfStudyOptions`], the Monte-Carlo study, which takes eight of the bank's options from
//! [`PfOptions`] (its field `filter`) rather than declaring them again. The Python signatures,
//! stubs, command-line flags and docs tables are checked against these declarations.

use crate::option_set;
use crate::options::{Named, OptionKind, OptionType, OptionValue};
use crate::pf::assignment::Assignment;
use crate::pf::bank::{Method, PfConfig};
use crate::pf::frame::Psf;
use crate::pf::motion::Ncv;
use crate::pf::peaks::PeakOptions;
use crate::pf::resample::Resampling;
use crate::pf::scenario::TruthModel;
use crate::pf::weights::LikelihoodModel;
use geofeas::error::Result;

option_set! {
    /// The options of a bank of particle filters (seed 003, Table 1).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct PfOptions {
        /// Particles per filter (the paper: 10,000).
        particles: usize = 10_000,
        /// Peak-to-filter assignment: the paper's weighted nearest neighbour, or distinct peaks.
        association: Assignment = Assignment::Nearest,
        /// Resampling scheme.
        resampling: Resampling = Resampling::Systematic,
        /// Resample when ESS < threshold x particles (1: every frame).
        resample_threshold: f64 = 1.0,
        /// Peaks extracted per frame (strongest local maxima).
        peaks: usize = 4,
        /// Least distance between two peaks, pixels.
        min_separation: f64 = 3.0,
        /// Gaussian smoothing of the frame before peak extraction, pixels (0: raw frame).
        smoothing: f64 = 0.0,
        /// Half-width of the uniform position initialisation, pixels.
        xmax: f64 = 3.0,
        /// Half-width of the uniform velocity initialisation, pixels/s.
        vmax: f64 = 0.5,
        /// Filter process noise, pixels/s^2 (the paper: 0.5).
        sigma_w: f64 = 0.5,
        /// Method 1 distance scale r1, pixels.
        r1: f64 = 1.0,
        /// Method 2 model as factors of (amplitude, blur, sigma_z) (the paper: 0.8, 1.5, 1.5).
        model_factors: [f64; 3] = [0.8, 1.5, 1.5],
        /// Method 2 likelihood window: +-half_box cells about each particle.
        half_box: usize = 10,
    }
}

option_set! {
    /// The options of a simulated run of the paper's scenario, beside [`PfOptions`].
    #[derive(Debug, Clone, PartialEq)]
    pub struct PfRunOptions {
        /// Signal-to-noise ratio, dB.
        snr_db: f64 = 15.0,
        /// Weighting: 1, distance to the associated peak; 2, the likelihood ratio.
        method: Method = Method::LikelihoodRatio,
        /// Seed of the study.
        seed: u64 = 0,
        /// Index of the run.
        run: u64 = 0,
        /// Truth model of Fig. 3: white, jerk, gauss-markov or ncv.
        truth: TruthKind = TruthKind::White,
        /// Frames at which resampled particles are returned.
        snapshot_frames: Vec<usize> = Vec::new(),
        /// Particles returned per filter and snapshot frame.
        snapshot_particles: usize = 300,
        /// Frames whose images are returned.
        keep_frames: Vec<usize> = Vec::new(),
    }
}

option_set! {
    /// The options of tracking given frames, beside [`PfOptions`] and the required `sigma_z`.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct PfTrackOptions {
        /// Weighting: 1, distance to the associated peak; 2, the likelihood ratio.
        method: Method = Method::LikelihoodRatio,
        /// Point-spread amplitude of the sensor.
        amplitude: f64 = 1.0,
        /// Point-spread blur (1-sigma) of the sensor, pixels.
        blur: f64 = 2.0,
        /// Time between frames, s.
        dt: f64 = 0.1,
        /// Seed of the filters' particles.
        seed: u64 = 0,
    }
}

option_set! {
    /// The options of the Monte-Carlo study (Figs. 7-20), with the filter options it takes from
    /// [`PfOptions`].
    #[derive(Debug, Clone, PartialEq)]
    pub struct PfStudyOptions {
        /// Monte-Carlo runs per row.
        runs: usize = 4,
        /// Seed of the random streams.
        seed: u64 = 0,
        /// Truth model of Fig. 3: white, jerk, gauss-markov or ncv.
        truth: TruthKind = TruthKind::White,
        /// SNRs of the Method 1 / 2 rows, dB (none: 0, 1, ..., 20).
        snrs: Option<Vec<f64>> = None,
        /// SNR of the initial-condition rows (Fig. 20), dB.
        ic_snr: f64 = 2.0,
        /// The bank's options every row takes (the rows set `xmax` and `vmax`, the paper the rest).
        filter: PfOptions {
            particles,
            association,
            resampling,
            peaks,
            min_separation,
            smoothing,
            sigma_w,
            model_factors,
        },
    }
}

impl PfOptions {
    /// The peak extraction, checked.
    pub fn peak_options(&self) -> Result<PeakOptions> {
        PeakOptions {
            count: self.peaks,
            min_separation: self.min_separation,
            smoothing: self.smoothing,
        }
        .validated()
    }

    /// The checked configuration of a bank weighting by `method` on frames of point spread
    /// `psf`, noise `sigma_z` and frame interval `dt`.
    pub fn config(&self, method: Method, psf: &Psf, sigma_z: f64, dt: f64) -> Result<PfConfig> {
        PfConfig {
            particles: self.particles,
            association: self.association,
            resampling: self.resampling,
            resample_threshold: self.resample_threshold,
            peaks: self.peak_options()?,
            xmax: self.xmax,
            vmax: self.vmax,
            r1: self.r1,
            motion: Ncv {
                dt,
                sigma_w: self.sigma_w,
            },
            model: LikelihoodModel {
                half_box: self.half_box,
                ..LikelihoodModel::scaled(psf, sigma_z, self.model_factors)
            },
            ..PfConfig::paper(method, psf, sigma_z)
        }
        .validated()
    }
}

/// The truth models of Fig. 3 by name, with the paper's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TruthKind {
    /// White accelerations drawn each step (the default).
    White,
    /// Accelerations driven by white jerk.
    Jerk,
    /// First-order Gauss-Markov accelerations.
    GaussMarkov,
    /// The filter's own nearly-constant-velocity model.
    Ncv,
}

impl TruthKind {
    /// The truth model with the paper's 1-sigma accelerations (0.5 / 1.0 pixels/s^2).
    pub fn model(self) -> TruthModel {
        let (sigma_l, sigma_n) = (0.5, 1.0);
        match self {
            Self::White => TruthModel::White { sigma_l, sigma_n },
            Self::Jerk => TruthModel::Jerk { sigma_l, sigma_n },
            Self::GaussMarkov => TruthModel::GaussMarkov {
                sigma_l,
                sigma_n,
                tau: 1.0,
            },
            Self::Ncv => TruthModel::Ncv { sigma_w: 0.5 },
        }
    }
}

impl Named for TruthKind {
    const NAMES: &'static [&'static str] = &["white", "jerk", "gauss-markov", "ncv"];
    fn name(&self) -> &'static str {
        Self::NAMES[*self as usize]
    }
    fn from_name(name: &str) -> Result<Self> {
        match name {
            "white" => Ok(Self::White),
            "jerk" => Ok(Self::Jerk),
            "gauss-markov" => Ok(Self::GaussMarkov),
            "ncv" => Ok(Self::Ncv),
            other => Err(crate::Error::InvalidOption {
                name: "truth",
                reason: format!("expected 'white', 'jerk', 'gauss-markov' or 'ncv', got '{other}'"),
            }),
        }
    }
}

impl OptionType for Method {
    const KIND: OptionKind = OptionKind::Int;
    fn to_value(&self) -> OptionValue {
        OptionValue::Int(u64::from(self.number()))
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        Method::from_number(u32::from_value(name, value)?)
    }
}

impl Named for Assignment {
    const NAMES: &'static [&'static str] = &["nearest", "one-to-one"];
    fn name(&self) -> &'static str {
        Assignment::name(self)
    }
    fn from_name(name: &str) -> Result<Self> {
        Assignment::from_name(name)
    }
}

impl Named for Resampling {
    const NAMES: &'static [&'static str] = &["systematic", "stratified", "multinomial", "residual"];
    fn name(&self) -> &'static str {
        Resampling::name(self)
    }
    fn from_name(name: &str) -> Result<Self> {
        Resampling::from_name(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::OptionSet;

    /// The defaults are the paper's configuration (Table 1).
    #[test]
    fn defaults_are_the_papers_configuration() {
        let psf = Psf::default();
        for method in [Method::PeakDistance, Method::LikelihoodRatio] {
            let ours = PfOptions::default().config(method, &psf, 0.2, 0.1).unwrap();
            assert_eq!(ours, PfConfig::paper(method, &psf, 0.2));
        }
    }

    /// Every name round-trips and every named option lists every name.
    #[test]
    fn names_round_trip() {
        fn check<T: Named + PartialEq + std::fmt::Debug>() {
            for n in T::NAMES {
                assert_eq!(T::from_name(n).unwrap().name(), *n);
            }
        }
        check::<TruthKind>();
        check::<Assignment>();
        check::<Resampling>();
        for m in [Method::PeakDistance, Method::LikelihoodRatio] {
            assert_eq!(Method::from_value("method", m.to_value()).unwrap(), m);
        }
        assert!(Method::from_value("method", OptionValue::Int(3)).is_err());
    }

    /// The study's filter options default as the bank's.
    #[test]
    fn study_filter_options_default_as_the_banks() {
        let bank = PfOptions::schema();
        for o in PfStudyOptions::schema() {
            if let Some(b) = bank.iter().find(|b| b.name == o.name) {
                assert_eq!((b.kind, &b.default, b.doc), (o.kind, &o.default, o.doc));
            }
        }
        let mut s = PfStudyOptions::default();
        s.set("truth", OptionValue::Text("ncv".into())).unwrap();
        assert_eq!(s.truth, TruthKind::Ncv);
        assert!(s
            .set("truth", OptionValue::Text("brownian".into()))
            .is_err());
    }
}
