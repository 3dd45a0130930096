import Foundation

/// Buildings shipped inside the Maps module (Maps/Buildings, a bundle resource).
public enum BundledMaps {
    /// File name of the bundled sample office.
    public static let officeFileName = "wayfinder-office.json"

    /// URL of a bundled building file, e.g. `officeFileName`; nil when not bundled. Under SwiftPM the files
    /// are the Maps module's resources (`Bundle.module`, folder `Buildings`); in the Xcode app build
    /// (project.yml copies Maps/Buildings into the app) they are in the main bundle.
    public static func url(forFile name: String) -> URL? {
        #if SWIFT_PACKAGE
        let roots = [Bundle.module.resourceURL]
        #else
        let roots = [Bundle.main.resourceURL]
        #endif
        for root in roots.compactMap({ $0 }) {
            for candidate in [root.appendingPathComponent("Buildings").appendingPathComponent(name), root.appendingPathComponent(name)]
            where FileManager.default.fileExists(atPath: candidate.path) {
                return candidate
            }
        }
        return nil
    }

    /// Loads and validates the bundled "Wayfinder Office" (two floors, elevator and two stairwells; made
    /// by `OfficeBuildingGenerator`).
    /// - Throws: `MapError` when the resource is missing or damaged (a packaging bug).
    public static func office() throws -> Building {
        guard let u = url(forFile: officeFileName) else {
            throw MapError(file: officeFileName, jsonPath: "$", reason: "bundled map resource is missing from the Maps bundle")
        }
        return try MapLoader.load(contentsOf: u)
    }
}

extension Building {
    /// The bundled "Wayfinder Office" (`BundledMaps.office()`).
    /// - Throws: `MapError` when the resource is missing or damaged.
    public static func bundledOffice() throws -> Building { try BundledMaps.office() }
}
