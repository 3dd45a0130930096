import Foundation
import Maps

/// Resolves a scenario's `map` string to a building.
public enum ScenarioMaps {
    /// Default location of the shared real data: `WAYFINDER_SHARED_DATA` when set, else `../shared/data` next
    /// to the current directory's repository (the project's convention).
    public static var defaultSharedDataDirectory: URL {
        if let env = ProcessInfo.processInfo.environment["WAYFINDER_SHARED_DATA"], !env.isEmpty {
            return URL(fileURLWithPath: env, isDirectory: true)
        }
        return URL(fileURLWithPath: FileManager.default.currentDirectoryPath).appendingPathComponent("../shared/data", isDirectory: true)
            .standardizedFileURL
    }

    /// Loads the building named by `spec`:
    /// - `office`: the bundled Wayfinder Office (`BundledMaps.office()`);
    /// - `skeri:<floor>` or `skeri`: the Smith-Kettlewell building imported from
    ///   `<sharedData>/skeri_inavigate` (all floors; the floor part names where the scenario walks);
    /// - anything else: a path to a map-v1 JSON file (`MapLoader.load(contentsOf:)`).
    /// - Throws: `SimulationError.mapUnavailable` naming the map and the cause.
    public static func load(_ spec: String, sharedData: URL? = nil) throws -> Building {
        do {
            if spec == "office" { return try BundledMaps.office() }
            if spec == "skeri" || spec.hasPrefix("skeri:") {
                let dir = (sharedData ?? defaultSharedDataDirectory).appendingPathComponent("skeri_inavigate", isDirectory: true)
                return try importSKERI(directory: dir)
            }
            return try MapLoader.load(contentsOf: URL(fileURLWithPath: spec))
        } catch let e as SimulationError {
            throw e
        } catch {
            throw SimulationError.mapUnavailable("\(spec): \(error)")
        }
    }

    /// Floor id named by a `skeri:<floor>` spec, if any.
    public static func skeriFloor(_ spec: String) -> String? {
        guard spec.hasPrefix("skeri:") else { return nil }
        return String(spec.dropFirst("skeri:".count))
    }

    /// Imported SKERI buildings by directory path (the import traces wall masks: worth doing once per process).
    nonisolated(unsafe) private static var skeriCache: [String: Building] = [:]
    private static let cacheLock = NSLock()

    static func importSKERI(directory: URL) throws -> Building {
        cacheLock.lock(); defer { cacheLock.unlock() }
        if let b = skeriCache[directory.path] { return b }
        guard FileManager.default.fileExists(atPath: directory.path) else {
            throw SimulationError.mapUnavailable("skeri: no iNavigate data at \(directory.path) (set WAYFINDER_SHARED_DATA)")
        }
        let b = try InavigateImporter.importBuilding(from: directory).building
        skeriCache[directory.path] = b
        return b
    }
}
