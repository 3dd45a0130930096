import Foundation

/// A partial set of noise-model parameters laid over complete ones: a JSON object whose keys are a subset of
/// `SimulationParameters`' (nested objects for the models, e.g. `{"vio": {"scaleErrorRange": [0.03, 0.10]}}`,
/// ranges as two-element arrays `[lower, upper]`). Used by `wayfinder simulate|eval --sim-params FILE` to run
/// the walks behind noise models other than docs/simulator.md's defaults (a stand-in for another generator's;
/// Tests/StressProfiles). Written by hand: Foundation's Codable has no merge of a partial document.
public enum SimulationParametersOverlay {
    /// What is wrong with an overlay document.
    public enum OverlayError: Error, CustomStringConvertible, Equatable {
        /// Not a JSON object, or not JSON at all.
        case notAnObject(String)
        /// A key that `SimulationParameters` does not have (dotted path, e.g. `vio.scaleErorRange`).
        case unknownKey(String)
        /// A value of the wrong type or shape for its key (the decoder's message).
        case badValue(String)
        /// The merged parameters fail `SimulationParameters.validate()` (its message).
        case invalid(String)

        /// One line naming the problem.
        public var description: String {
            switch self {
            case .notAnObject(let s): return "not a JSON object of simulation parameters: \(s)"
            case .unknownKey(let k): return "unknown simulation parameter '\(k)'"
            case .badValue(let s): return "bad value: \(s)"
            case .invalid(let s): return "invalid parameters: \(s)"
            }
        }
    }

    /// `base` with every key of the JSON object `overlay` replaced by the overlay's value (objects merged key
    /// by key, everything else replaced whole). Throws `OverlayError` for a document that is not an object, a
    /// key `base` does not have (a misspelt key must not silently leave the default in place), a value the
    /// parameters cannot decode, or merged parameters that fail validation.
    public static func apply(_ overlay: Data, to base: SimulationParameters) throws -> SimulationParameters {
        let top: Any
        do { top = try JSONSerialization.jsonObject(with: overlay) } catch {
            throw OverlayError.notAnObject(error.localizedDescription)
        }
        guard let patch = top as? [String: Any] else { throw OverlayError.notAnObject("the top level is not an object") }
        let encoded = try JSONEncoder().encode(base)
        guard let current = try JSONSerialization.jsonObject(with: encoded) as? [String: Any] else {
            throw OverlayError.notAnObject("the base parameters did not encode as an object")
        }
        let merged = try merge(patch, into: current, path: "")
        let data = try JSONSerialization.data(withJSONObject: merged)
        let result: SimulationParameters
        do { result = try JSONDecoder().decode(SimulationParameters.self, from: data) } catch let error as DecodingError {
            throw OverlayError.badValue(describe(error))
        }
        do { try result.validate() } catch { throw OverlayError.invalid("\(error)") }
        return result
    }

    /// Merges `patch` into `base` recursively; `path` is the dotted key path of `base` (for errors).
    private static func merge(_ patch: [String: Any], into base: [String: Any], path: String) throws -> [String: Any] {
        var out = base
        for key in patch.keys.sorted() {
            let value = patch[key]!
            let keyPath = path.isEmpty ? key : "\(path).\(key)"
            guard let existing = base[key] else { throw OverlayError.unknownKey(keyPath) }
            if let sub = value as? [String: Any] {
                guard let baseSub = existing as? [String: Any] else {
                    throw OverlayError.badValue("'\(keyPath)' is not a group of parameters")
                }
                out[key] = try merge(sub, into: baseSub, path: keyPath)
            } else {
                out[key] = value
            }
        }
        return out
    }

    /// The decoder's error as "key path: problem".
    private static func describe(_ error: DecodingError) -> String {
        func path(_ c: DecodingError.Context) -> String { c.codingPath.map(\.stringValue).joined(separator: ".") }
        switch error {
        case .typeMismatch(_, let c), .valueNotFound(_, let c), .dataCorrupted(let c):
            return "\(path(c)): \(c.debugDescription)"
        case .keyNotFound(let k, let c):
            return "\(path(c)): missing \(k.stringValue)"
        @unknown default:
            return "\(error)"
        }
    }
}
