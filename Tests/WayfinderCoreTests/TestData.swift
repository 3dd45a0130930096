import Foundation
import Maps
import SessionFormat

/// Paths of committed test data, relative to this file.
enum TestData {
    static let packageRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent()
        .deletingLastPathComponent()
    static let sampleBundle = packageRoot.appendingPathComponent("App/Samples/office-walk")
    static let officeMap = packageRoot.appendingPathComponent("Maps/Buildings/wayfinder-office.json")

    static func office() throws -> Building { try MapLoader.load(contentsOf: officeMap) }
    static func sample() throws -> SessionBundle { try SessionBundle.read(from: sampleBundle) }
}
