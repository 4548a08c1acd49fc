//! Transcription in progress; see `crate::audit`.

/// The formulas of this module, with their samplers.
pub fn audits() -> Vec<crate::audit::Audit> {
    Vec::new()
}

/// The chain rules of this module.
pub fn chains() -> Vec<crate::audit::chain::Chain> {
    Vec::new()
}
