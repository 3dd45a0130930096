import Foundation

/// Buildings shipped inside the Maps module (Maps/Buildings, a bundle resource).
public enum BundledMaps {
    /// File name of the bundled sample office.
    public static let officeFileName = "wayfinder-office.json"

    /// URL of a bundled building file, e.g. `officeFileName`; nil when not bundled.
    public static func url(forFile name: String) -> URL? {
        let url = Bundle.module.resourceURL?.appendingPathComponent("Buildings").appendingPathComponent(name)
        guard let u = url, FileManager.default.fileExists(atPath: u.path) else { return nil }
        return u
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
