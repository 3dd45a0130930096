import Foundation
import XCTest
@testable import Maps

final class MapLoaderTests: XCTestCase {
    func testRoundTripPreservesEveryField() throws {
        let b = MapFixtures.building()
        let loaded = try MapLoader.load(data: try MapWriter.encode(b), fileName: "x.json")
        XCTAssertEqual(loaded, b)
        XCTAssertEqual(loaded.floors[1].signs[0].mountingHeightMeters, nil)
        XCTAssertEqual(loaded.floors[1].signs[0].doubleSided, true)
        XCTAssertEqual(loaded.floors[0].doors[0].label, "East door")
    }

    func testCompassHeadingOfMapNorthRoundTripsAndIsRangeChecked() throws {
        var b = MapFixtures.building()
        XCTAssertNil(b.compassHeadingOfMapNorthDeg)
        b.compassHeadingOfMapNorthDeg = 350.9
        XCTAssertEqual(try MapLoader.load(data: try MapWriter.encode(b), fileName: "n.json").compassHeadingOfMapNorthDeg, 350.9)
        for bad in [360.0, -1.0] {
            b.compassHeadingOfMapNorthDeg = bad
            XCTAssertThrowsError(try MapLoader.load(data: try MapWriter.encode(b), fileName: "n.json")) { e in
                XCTAssertTrue("\(e)".contains("n.json") && "\(e)".contains("compassHeadingOfMapNorthDeg"), "\(e)")
            }
        }
    }

    func testWriterSortsKeysAndWritesPointsOnOneLine() throws {
        let t = try MapFixtures.text()
        XCTAssertTrue(t.contains("\"facing\" : [1, 0]"))
        let building = try XCTUnwrap(t.range(of: "\"floors\"")), format = try XCTUnwrap(t.range(of: "\"formatVersion\""))
        XCTAssertLessThan(building.lowerBound, format.lowerBound)
        XCTAssertEqual(try MapFixtures.text(), t, "deterministic output")
    }

    func testOptionalMembersTakeTheirDefaults() throws {
        let json = """
        {"formatVersion": 1, "id": "tiny", "name": "Tiny",
         "floors": [{"id": "G", "name": "Ground", "elevationMeters": 0,
                     "walls": [{"from": [0, 0], "to": [4, 0]}],
                     "signs": [{"id": "s", "kind": "exit", "position": [2, 0], "facing": [0, 1], "widthMeters": 0.3, "heightMeters": 0.2}],
                     "pointsOfInterest": [{"id": "p", "name": "Desk", "category": "office", "position": [1, 1]}]}],
         "graph": {"nodes": [{"id": "n", "kind": "pointOfInterest", "floorId": "G", "position": [1, 1], "pointOfInterestId": "p"}],
                   "edges": []},
         "x-comment": "extension members are ignored", "$schema": "../schema/map-v1.schema.json"}
        """
        let b = try MapLoader.load(data: Data(json.utf8), fileName: "tiny.json")
        XCTAssertEqual(b.floors[0].doors, [])
        XCTAssertEqual(b.floors[0].signs[0].doubleSided, false)
        XCTAssertEqual(b.floors[0].signs[0].placement, .wall)
        XCTAssertNil(b.floors[0].signs[0].mountingHeightMeters)
        XCTAssertEqual(b.floors[0].pointsOfInterest[0].behindDoor, false)
        XCTAssertEqual(b.graph.edges, [])
        // JSONDecoder (no validation) applies the same defaults.
        XCTAssertEqual(try JSONDecoder().decode(Building.self, from: Data(json.utf8)), b)
    }

    func testLoadFromURLNamesTheFileAndMissingFile() throws {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("maps-loader-\(UUID().uuidString)")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(at: dir) }
        let good = dir.appendingPathComponent("good.json")
        try MapWriter.write(MapFixtures.building(), to: good)
        XCTAssertEqual(try MapLoader.load(contentsOf: good), MapFixtures.building())

        let bad = dir.appendingPathComponent("broken.json")
        try Data("{\"formatVersion\": 1,".utf8).write(to: bad)
        XCTAssertThrowsError(try MapLoader.load(contentsOf: bad)) { e in
            XCTAssertEqual((e as? MapError)?.file, "broken.json")
            XCTAssertTrue("\(e)".hasPrefix("broken.json: $: not valid JSON: line 1, column 21"), "\(e)")
        }
        XCTAssertThrowsError(try MapLoader.load(contentsOf: dir.appendingPathComponent("absent.json"))) { e in
            XCTAssertEqual((e as? MapError)?.file, "absent.json")
            XCTAssertTrue((e as? MapError)?.reason.contains("no such file") ?? false)
        }
    }

    func testSyntaxErrorsGiveLineAndColumn() {
        let text = "{\n  \"formatVersion\": 1,\n  \"id\": \"x\",,\n}"
        XCTAssertThrowsError(try MapLoader.load(data: Data(text.utf8), fileName: "f.json")) { e in
            XCTAssertEqual("\(e)", "f.json: $: not valid JSON: line 3, column 13: expected a member name in double quotes, found ','")
        }
        XCTAssertThrowsError(try MapLoader.load(data: Data("[1, 2,]".utf8), fileName: "f.json"), "trailing commas are refused")
    }

    /// Never a crash: every prefix of a valid file and deeply nested input are rejected with a MapError.
    func testEveryTruncationIsRejectedCleanly() throws {
        let data = try MapWriter.encode(MapFixtures.building())
        var rejected = 0
        for n in stride(from: 0, to: data.count - 1, by: 7) {
            do {
                _ = try MapLoader.load(data: data.prefix(n), fileName: "cut.json")
                XCTFail("prefix of \(n) bytes loaded")
            } catch is MapError { rejected += 1 }
        }
        XCTAssertGreaterThan(rejected, 100)
        let deep = String(repeating: "[", count: 100_000)
        XCTAssertThrowsError(try MapLoader.load(data: Data(deep.utf8), fileName: "deep.json")) { e in
            XCTAssertTrue("\(e)".contains("nesting deeper than"))
        }
    }

    func testStringEscapesAndUnicode() throws {
        let text = try MapFixtures.text(replacing: "\"name\" : \"Room B\"", with: "\"name\" : \"Caf\\u00e9 \\\"B\\\" \\ud83d\\ude80\"")
        let b = try MapLoader.load(data: Data(text.utf8), fileName: "u.json")
        XCTAssertEqual(b.floors[1].pointsOfInterest[0].name, "Café \"B\" 🚀")
    }

    func testJSONDecoderAgreesWithLoaderOnWrittenFiles() throws {
        // The synthesized Codable conformances read what MapWriter writes (for code that uses JSONDecoder).
        let data = try MapWriter.encode(MapFixtures.building())
        XCTAssertEqual(try JSONDecoder().decode(Building.self, from: data), MapFixtures.building())
    }
}

/// The JSON Schema and the loader agree on member names.
final class MapSchemaTests: XCTestCase {
    static var schemaURL: URL {
        URL(fileURLWithPath: #filePath).resolvingSymlinksInPath().deletingLastPathComponent().deletingLastPathComponent()
            .deletingLastPathComponent().appendingPathComponent("Maps/schema/map-v1.schema.json")
    }

    /// Every member name in `value` (recursively).
    static func memberNames(_ value: JSONValue, into names: inout Set<String>) {
        switch value {
        case .object(let members): for (k, v) in members { names.insert(k); memberNames(v, into: &names) }
        case .array(let items): for v in items { memberNames(v, into: &names) }
        default: break
        }
    }

    func testSchemaIsDraft202012AndCoversEveryMemberTheWriterWrites() throws {
        let schema = try JSONParser.parse([UInt8](try Data(contentsOf: Self.schemaURL)))
        guard case .object(let top) = schema else { return XCTFail("schema is not an object") }
        guard case .string(let dialect)? = top.first(where: { $0.key == "$schema" })?.value else { return XCTFail("no $schema") }
        XCTAssertEqual(dialect, "https://json-schema.org/draft/2020-12/schema")
        var schemaNames = Set<String>()
        Self.memberNames(schema, into: &schemaNames)
        var b = MapFixtures.building()
        b.floors[0].signs[0].positionAdjustmentMeters = 0.1
        b.floors[0].signs[0].placement = .projecting
        for data in [try MapWriter.encode(b), try MapWriter.encode(OfficeBuildingGenerator.makeBuilding())] {
            var written = Set<String>()
            Self.memberNames(try JSONParser.parse([UInt8](data)), into: &written)
            XCTAssertTrue(written.isSubset(of: schemaNames), "not in the schema: \(written.subtracting(schemaNames).sorted())")
        }
    }
}
