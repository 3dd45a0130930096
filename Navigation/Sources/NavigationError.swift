import Foundation

/// Why a navigator, routing graph or phrase book could not be built. Each message names the offending
/// item (node id, edge index, file, key) so that a bad map or locale file can be fixed without a debugger.
public enum NavigationError: Error, CustomStringConvertible, Equatable, Sendable {
    /// The graph is inconsistent (unknown node in an edge, duplicate id, node on an unknown floor...).
    case invalidGraph(String)
    /// The destination id names neither a point of interest nor a graph node.
    case unknownDestination(String)
    /// No phrase file for this language in `Navigation/Locales`.
    case unknownLanguage(String)
    /// A phrase file is unreadable, or lacks a key, or uses a placeholder the code does not fill.
    case invalidPhraseFile(String)

    /// Human-readable message.
    public var description: String {
        switch self {
        case .invalidGraph(let m): return "invalid navigation graph: \(m)"
        case .unknownDestination(let id):
            return "unknown destination '\(id)': not a point-of-interest id nor a graph node id"
        case .unknownLanguage(let l): return "no phrase file Navigation/Locales/\(l).json for language '\(l)'"
        case .invalidPhraseFile(let m): return "invalid phrase file: \(m)"
        }
    }
}
