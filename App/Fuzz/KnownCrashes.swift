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
    // Empty: the MapValidator.fmt trap (Maps/Sources/MapValidation.swift) and Foundation's JSONDecoder
    // 512-level nesting trap in the bundle reader (now refused first: App/SessionFormat/JSONNesting.swift)
    // were fixed in the commits that merged this harness.
]
