//! One small deterministic random-number generator (SplitMix64) for the
//! searches that need randomness: seeded, so the same recipe gives the same
//! design on every run, and no extra crate for a dozen lines. It is the rod
//! solver's generator (its seeded perturbations), written once there.

pub(crate) use karigami_rods::rng::Rng;
