import Foundation
import XCTest
@testable import Maps

/// A small valid two-floor building used by the loader and validation tests, and helpers to damage it.
enum MapFixtures {
    /// File name used in every error-message assertion.
    static let fileName = "fixture-map.json"

    /// Floor 1 (elevation 0) and floor 2 (elevation 3.5): each a 10 x 4 m room, an Exit sign on the west
    /// wall, a point of interest and an elevator joined across floors.
    static func building() -> Building {
        func room() -> [Wall] {
            [Wall(from: Point2(0, 0), to: Point2(10, 0)), Wall(from: Point2(10, 0), to: Point2(10, 4)),
             Wall(from: Point2(10, 4), to: Point2(0, 4)), Wall(from: Point2(0, 4), to: Point2(0, 0))]
        }
        let f1 = Floor(id: "1", name: "Ground floor", elevationMeters: 0, walls: room(),
                       doors: [Door(id: "d1", position: Point2(10, 2), widthMeters: 0.9, label: "East door")],
                       signs: [Sign(id: "s1", kind: "exit", position: Point2(0, 2), facing: Point2(1, 0), widthMeters: 0.3,
                                    heightMeters: 0.21, mountingHeightMeters: 2.3, doubleSided: false)],
                       pointsOfInterest: [PointOfInterest(id: "poi-a", name: "Room A", category: "room", position: Point2(2, 2), behindDoor: true)])
        let f2 = Floor(id: "2", name: "Upper floor", elevationMeters: 3.5, walls: room(),
                       signs: [Sign(id: "s2", kind: "exit", position: Point2(5, 4), facing: Point2(0, -1), widthMeters: 0.31,
                                    heightMeters: 0.22, mountingHeightMeters: nil, doubleSided: true)],
                       pointsOfInterest: [PointOfInterest(id: "poi-b", name: "Room B", category: "office", position: Point2(2.5, 1.5), behindDoor: false)])
        let nodes = [
            GraphNode(id: "a", kind: .pointOfInterest, floorId: "1", position: Point2(2, 2), label: "Room A", pointOfInterestId: "poi-a"),
            GraphNode(id: "c1", kind: .control, floorId: "1", position: Point2(5, 2)),
            GraphNode(id: "e1", kind: .verticalLink, floorId: "1", position: Point2(8, 2), label: "Elevator", verticalLink: .elevator),
            GraphNode(id: "e2", kind: .verticalLink, floorId: "2", position: Point2(8, 2), label: "Elevator", verticalLink: .elevator),
            GraphNode(id: "c2", kind: .control, floorId: "2", position: Point2(5, 2)),
            GraphNode(id: "b", kind: .pointOfInterest, floorId: "2", position: Point2(2.5, 2), pointOfInterestId: "poi-b"),
        ]
        let edges = [GraphEdge(from: "a", to: "c1", throughDoor: true), GraphEdge(from: "c1", to: "e1"),
                     GraphEdge(from: "e1", to: "e2"), GraphEdge(from: "e2", to: "c2"), GraphEdge(from: "c2", to: "b")]
        return Building(id: "fixture", name: "Fixture building", floors: [f1, f2], graph: NavigationGraph(nodes: nodes, edges: edges))
    }

    /// The fixture's file text (MapWriter output).
    static func text() throws -> String { String(decoding: try MapWriter.encode(building()), as: UTF8.self) }

    /// The fixture's text with `old` (which must occur exactly once) replaced by `new`.
    static func text(replacing old: String, with new: String, file: StaticString = #filePath, line: UInt = #line) throws -> String {
        let t = try text()
        XCTAssertEqual(t.components(separatedBy: old).count, 2, "fixture text must contain \(old) exactly once", file: file, line: line)
        return t.replacingOccurrences(of: old, with: new)
    }

    /// The fixture's text with the first occurrence of `old` replaced by `new`.
    static func text(replacingFirst old: String, with new: String) throws -> String {
        let t = try text()
        guard let r = t.range(of: old) else { XCTFail("fixture text lacks \(old)"); return t }
        return t.replacingCharacters(in: r, with: new)
    }

    /// Encodes a (possibly damaged) building without validation.
    static func text(of b: Building) throws -> String { String(decoding: try MapWriter.encodeUnvalidated(b), as: UTF8.self) }
}

extension XCTestCase {
    /// Loads `text` as `MapFixtures.fileName` and asserts that it is rejected with exactly `path` and a
    /// reason containing `reason`, and that the message names the file, the path and the reason.
    func assertRejects(_ text: String, path: String, reason: String, file: StaticString = #filePath, line: UInt = #line) {
        do {
            _ = try MapLoader.load(data: Data(text.utf8), fileName: MapFixtures.fileName)
            XCTFail("expected the map to be rejected at \(path) (\(reason))", file: file, line: line)
        } catch let e as MapError {
            XCTAssertEqual(e.file, MapFixtures.fileName, file: file, line: line)
            XCTAssertEqual(e.jsonPath, path, "\(e)", file: file, line: line)
            XCTAssertTrue(e.reason.contains(reason), "reason \"\(e.reason)\" does not contain \"\(reason)\"", file: file, line: line)
            let message = e.description
            XCTAssertTrue(message.contains(MapFixtures.fileName) && message.contains(path) && message.contains(reason),
                          "message \"\(message)\"", file: file, line: line)
        } catch {
            XCTFail("expected MapError, got \(error)", file: file, line: line)
        }
    }

    /// Damages the fixture building with `damage`, writes it without validation and asserts the rejection.
    func assertRejects(damage: (inout Building) -> Void, path: String, reason: String, file: StaticString = #filePath, line: UInt = #line) throws {
        var b = MapFixtures.building()
        damage(&b)
        assertRejects(try MapFixtures.text(of: b), path: path, reason: reason, file: file, line: line)
    }
}
