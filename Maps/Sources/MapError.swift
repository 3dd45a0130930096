/// Why a map file (or an in-memory `Building`) was rejected: the file, the JSON path of the offending
/// value and the reason, e.g. `office.json: $.floors[1].signs[3].facing: facing must be a unit vector
/// (length 0.50)`. Thrown by `MapLoader` and `MapValidator`; a rejected map is never partly loaded.
public struct MapError: Error, CustomStringConvertible, Equatable, Sendable {
    /// The file's name as given to the loader (its last path component for `load(contentsOf:)`),
    /// or "<memory>" for a building validated in memory.
    public var file: String
    /// JSONPath of the offending value: `$` is the document, `$.floors[1].signs[3].facing` a member.
    /// For a building built in code the path is where the value would be in its file.
    public var jsonPath: String
    /// What is wrong, in words, with the offending value where that helps.
    public var reason: String

    /// Creates an error.
    public init(file: String, jsonPath: String, reason: String) {
        self.file = file; self.jsonPath = jsonPath; self.reason = reason
    }

    /// `file: jsonPath: reason`.
    public var description: String { "\(file): \(jsonPath): \(reason)" }
}

/// An error found at a JSON path before the file name is known (internal; MapLoader adds the file).
struct PathError: Error {
    /// JSONPath of the offending value.
    let path: String
    /// What is wrong.
    let reason: String
    /// Adds the file name.
    func mapError(file: String) -> MapError { MapError(file: file, jsonPath: path, reason: reason) }
}
