/// A crash already reported and being fixed elsewhere, which a campaign counts but does not fail on.
///
/// Policy (docs/fuzzing.md, "Known crashes"): an entry is added only for a crash with an open fix in a
/// file this harness's owner may not change, names the fix, and is removed when the fix is merged; the
/// list is meant to be empty. A crash matches when it happened in `target` and the worker's crash report
/// (the Swift runtime's message and backtrace on standard error) contains every string of `reportContains`.
struct KnownCrash {
    /// Target name.
    let target: String
    /// Substrings that must all appear in the crash report.
    let reportContains: [String]
    /// Why it is known and where it is being fixed.
    let note: String
}

/// The known-crash list. Remove an entry in the commit that merges its fix; when the list is empty every
/// crash fails a campaign.
let knownCrashes: [KnownCrash] = [
    // MapValidator.fmt (Maps/Sources/MapValidation.swift) formats an out-of-range number for its error
    // message with Int(r): |value| >= 2^63 traps "greater than Int.max", and |value| > ~1.8e305 overflows
    // (v * 1000) to infinity and traps "infinite or NaN". Reached from the map loader and from the iNavigate
    // importer (which validates what it converts). Being fixed by the Maps/ helper (issue 14).
    KnownCrash(target: "map", reportContains: ["MapValidator.fmt"], note: "MapValidator.fmt, Maps/ fix pending"),
    KnownCrash(target: "inavigate", reportContains: ["MapValidator.fmt"], note: "MapValidator.fmt, Maps/ fix pending"),
    // Foundation's JSONDecoder (swift-foundation in the Swift 6.3.1 toolchain) traps in
    // JSONError.SourceLocation.sourceLocation(at:fullSource:) when the text ends exactly at its 512-level
    // nesting limit: a frames.jsonl line of 513 '[' crashes SessionBundle.read. Reported to the
    // App/SessionFormat (JSON-lines reader) helper; the OCCaM importer guards against it itself.
    KnownCrash(target: "bundle", reportContains: ["JSONError.SourceLocation"], note: "JSONDecoder 512-level trap, SessionFormat fix pending"),
]
