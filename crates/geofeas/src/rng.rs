//! Seeded random streams: one independent xoshiro256++ stream per `(seed, index)`.
//!
//! Every randomised computation of the crate (Monte-Carlo pairs, posterior chains, simulated
//! runs, particle filters) derives its stream from an explicit seed and the index of the item
//! it works on, so results are bit-identical whatever the number of threads. The index and the
//! seed are decorrelated by the SplitMix64 finaliser (Steele, Lea & Flood 2014), whose output
//! seeds the generator.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

/// SplitMix64 finaliser: decorrelates `(seed, index)` into a stream seed.
///
/// ```
/// use geofeas::rng::mix64;
/// assert_ne!(mix64(1), mix64(2));
/// assert_eq!(mix64(0), 0xe220_a839_7b1d_cdaf);
/// ```
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random stream of item `index` under `seed`.
pub fn stream(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(mix64(seed ^ mix64(index)))
}
