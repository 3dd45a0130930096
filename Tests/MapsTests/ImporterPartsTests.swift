import Foundation
import XCTest
@testable import Maps

/// The importer's parts on small made-up inputs: BMP reader, flat YAML reader, wall tracer.
final class ImporterPartsTests: XCTestCase {
    /// A 24-bit bottom-up BMP with row padding (width 3 -> 9 bytes per row padded to 12).
    func testReads24BitBottomUpWithPadding() throws {
        let w = 3, h = 2, stride = 12
        var b = [UInt8]()
        func p32(_ v: Int) { for k in 0..<4 { b.append(UInt8((v >> (8 * k)) & 0xFF)) } }
        func p16(_ v: Int) { for k in 0..<2 { b.append(UInt8((v >> (8 * k)) & 0xFF)) } }
        b += Array("BM".utf8); p32(54 + stride * h); p32(0); p32(54)
        p32(40); p32(w); p32(h); p16(1); p16(24); p32(0); p32(stride * h); p32(0); p32(0); p32(0); p32(0)
        // File row 0 = bottom picture row: white, black, white(ish red).
        b += [255, 255, 255, 0, 0, 0, 0, 0, 255, 0, 0, 0]
        // File row 1 = top picture row: black, white, black.
        b += [0, 0, 0, 255, 255, 255, 0, 0, 0, 0, 0, 0]
        let img = try BMPReader.decode(Data(b), file: "t.bmp")
        XCTAssertEqual(img.width, 3); XCTAssertEqual(img.height, 2)
        XCTAssertEqual(img.pixels, [0, 255, 0, 255, 0, 76])
        XCTAssertEqual(img[1, 0], 255)
    }

    func testEightBitRoundTripAndDamage() throws {
        let img = GrayImage(width: 5, height: 3, pixels: (0..<15).map { UInt8($0 * 17) })
        let data = BMPReader.encodeGray(img)
        let back = try BMPReader.decode(data, file: "g.bmp")
        XCTAssertEqual(back.pixels, img.pixels)
        XCTAssertThrowsError(try BMPReader.decode(data.prefix(data.count - 3), file: "g.bmp")) { e in
            XCTAssertTrue("\(e)".hasPrefix("g.bmp: truncated pixel data"), "\(e)")
        }
        XCTAssertThrowsError(try BMPReader.decode(Data("PNG....".utf8) + Data(count: 60), file: "g.bmp")) { e in
            XCTAssertTrue("\(e)".contains("no 'BM' signature"))
        }
    }

    /// Never a crash: 2,000 corrupted copies of a valid BMP (fixed-seed bytes in the headers and pixels,
    /// random truncation) either decode or throw BMPError.
    func testCorruptedBMPsNeverCrash() {
        let base = [UInt8](BMPReader.encodeGray(GrayImage(width: 7, height: 5, pixels: (0..<35).map { UInt8($0 * 7) })))
        var state: UInt64 = 0x9E37_79B9_7F4A_7C15
        func next() -> Int { state = state &* 6364136223846793005 &+ 1442695040888963407; return Int(state >> 33) }
        var thrown = 0
        for _ in 0..<2000 {
            var b = base
            for _ in 0..<(1 + next() % 4) { b[next() % 60] = UInt8(next() % 256) }
            if next() % 3 == 0 { b = Array(b.prefix(next() % b.count)) }
            do { _ = try BMPReader.decode(Data(b), file: "fuzz.bmp") } catch is BMPError { thrown += 1 } catch { XCTFail("\(error)") }
        }
        XCTAssertGreaterThan(thrown, 500)
    }

    func testYAMLWithTabsAndBothListStyles() throws {
        let text = "%YAML:1.0\nmap_feature:\n\tid: 0\n\ttype: exit_sign\n\tposition: [9.3103   17.4138]\n    normal: [1, 0]\n    height: 2.38\nmap_feature:\n    id: 1\n    position: [31.1207, 5.1724]\nbuilding_name: SKERI # comment\n"
        let y = try SimpleYAML(text: text, file: "f.yml")
        XCTAssertEqual(y.records.count, 2)
        XCTAssertEqual(y.records[0].fields["type"], "exit_sign")
        XCTAssertEqual(SimpleYAML.numbers(y.records[0].fields["position"]!), [9.3103, 17.4138])
        XCTAssertEqual(SimpleYAML.numbers(y.records[1].fields["position"]!), [31.1207, 5.1724])
        XCTAssertEqual(y.records[0].fields["height"], "2.38")
        XCTAssertEqual(y.scalars["building_name"], "SKERI")
        XCTAssertNil(SimpleYAML.numbers("[1, x]"))
        XCTAssertThrowsError(try SimpleYAML(text: "floor:\n  id 4\n", file: "i.yml")) { e in
            XCTAssertEqual("\(e)", "i.yml:2: expected 'key: value', got \"id 4\"")
        }
    }

    func testTracerMergesRunsIntoMaximalSegments() {
        // A 4 x 1 bar of wall in a 6 x 3 image: one rectangle outline = 4 merged segments.
        var mask = [Bool](repeating: false, count: 18)
        for c in 1...4 { mask[1 * 6 + c] = true }
        let segs = Set(WallTracer.trace(mask: mask, width: 6, height: 3))
        XCTAssertEqual(segs, [
            .init(from: Point2(1, 1), to: Point2(5, 1)), .init(from: Point2(1, 2), to: Point2(5, 2)),
            .init(from: Point2(1, 1), to: Point2(1, 2)), .init(from: Point2(5, 1), to: Point2(5, 2)),
        ])
        // A speck of 1 pixel disappears with minimumComponentPixels 2. Kept, it touches the bar at a corner:
        // its bottom edge continues the bar's top face and its right edge the bar's left end (collinear
        // runs merge), so it adds 2 segments (its top and left edges).
        var speck = mask
        speck[0] = true
        XCTAssertEqual(WallTracer.trace(mask: speck, width: 6, height: 3).count, 6)
        XCTAssertEqual(WallTracer.trace(mask: speck, width: 6, height: 3, minimumComponentPixels: 2).count, 4)
    }

    func testSlugAndCategory() {
        XCTAssertEqual(InavigateImporter.slug("Men's restroom"), "mens-restroom")
        XCTAssertEqual(InavigateImporter.slug("  EEG lab!! 2 "), "eeg-lab-2")
        XCTAssertEqual(InavigateImporter.category(of: "women's restroom", isDoor: true), "restroom")
        XCTAssertEqual(InavigateImporter.category(of: "main stairwell", isDoor: true), "stairs")
        XCTAssertEqual(InavigateImporter.category(of: "elevator", isDoor: false), "elevator")
        XCTAssertEqual(InavigateImporter.category(of: "Giovanni's office", isDoor: true), "office")
        XCTAssertEqual(InavigateImporter.category(of: "EEG lab", isDoor: true), "room")
        XCTAssertEqual(InavigateImporter.category(of: "water cooler", isDoor: false), "amenity")
    }

    func testImporterRejectsMissingAndDamagedFiles() throws {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("inav-\(UUID().uuidString)")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(at: dir) }
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertEqual("\(e)", "\(dir.appendingPathComponent("info.yml").path): no such file")
        }
        try "building_name: T\nfloor:\n    id: 1\n    features_file: f.yml\n    walls: w.bmp\n    scale: 10\n".write(
            to: dir.appendingPathComponent("info.yml"), atomically: true, encoding: .utf8)
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertEqual("\(e)", "\(dir.appendingPathComponent("w.bmp").path): no such file")
        }
        try Data("BMxx".utf8).write(to: dir.appendingPathComponent("w.bmp"))
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertTrue("\(e)".hasPrefix(dir.appendingPathComponent("w.bmp").path + ": not a BMP file"), "\(e)")
        }
        var px = [UInt8](repeating: 0, count: 20 * 10)
        for c in 0..<20 { px[c] = 255; px[9 * 20 + c] = 255 }
        try BMPReader.encodeGray(GrayImage(width: 20, height: 10, pixels: px)).write(to: dir.appendingPathComponent("w.bmp"))
        try "map_feature:\n    id: 0\n    type: exit_sign\n    position: [1.0 oops]\n    normal: [0, 1]\n".write(
            to: dir.appendingPathComponent("f.yml"), atomically: true, encoding: .utf8)
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertEqual("\(e)", "\(dir.appendingPathComponent("f.yml").path): map_feature at line 1: 'position' must be [a, b] in meters")
        }
        // A sign 0.05 m above the bottom wall's top face, facing north: snapped onto it (x = 1, y = 0.9).
        try "map_feature:\n    id: 0\n    type: exit_sign\n    position: [1.0, 0.15]\n    normal: [0, 1]\n".write(
            to: dir.appendingPathComponent("f.yml"), atomically: true, encoding: .utf8)
        try "{\"nodes\": {\"1\": {\"id\": 1, \"type\": \"destination\", \"position\": [5, 5], \"floor\": \"1\", \"label\": \"kitchen\", \"isDoor\": 1},".write(
            to: dir.appendingPathComponent("navgraph.json"), atomically: true, encoding: .utf8)
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertTrue("\(e)".hasPrefix(dir.appendingPathComponent("navgraph.json").path + ": not valid JSON"), "\(e)")
        }
        try "{\"nodes\": {\"1\": {\"id\": 1, \"type\": \"destination\", \"position\": [5, 5], \"floor\": \"1\", \"label\": \"kitchen\", \"isDoor\": 1}}, \"weights\": [[0]]}".write(
            to: dir.appendingPathComponent("navgraph.json"), atomically: true, encoding: .utf8)
        let (b, report) = try InavigateImporter.importBuilding(from: dir)
        XCTAssertEqual(report.first?.signs, 1)
        let s = b.floors[0].signs[0]
        XCTAssertEqual(s.placement, .wall)
        XCTAssertEqual(s.position.x, 1.0, accuracy: 1e-12)
        XCTAssertEqual(s.position.y, 0.1, accuracy: 1e-12)   // bottom wall row 9 of 10 at 10 px/m: top face y = 0.1
        XCTAssertEqual(s.positionAdjustmentMeters ?? -1, 0.05, accuracy: 1e-9)
        XCTAssertEqual(b.pointOfInterest(id: "kitchen-1f")?.position, Point2(0.5, 0.5))
        XCTAssertEqual(b.pointOfInterest(id: "kitchen-1f")?.behindDoor, true)
    }
}

/// Inputs found by wayfinder-fuzz (docs/fuzzing.md) that used to trap the importer instead of throwing.
final class InavigateImporterFuzzRegressionTests: XCTestCase {
    /// A valid one-floor folder (20 x 10 px room at 10 px/m, one exit sign, one destination), with
    /// `info` and `graph` replacing info.yml and navgraph.json.
    private func folder(info: String, graph: String) throws -> URL {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("inav-fuzz-\(UUID().uuidString)")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        addTeardownBlock { try? FileManager.default.removeItem(at: dir) }
        var px = [UInt8](repeating: 0, count: 20 * 10)
        for c in 0..<20 { px[c] = 255; px[9 * 20 + c] = 255 }
        try BMPReader.encodeGray(GrayImage(width: 20, height: 10, pixels: px)).write(to: dir.appendingPathComponent("w.bmp"))
        try "map_feature:\n    id: 0\n    type: exit_sign\n    position: [1.0, 0.15]\n    normal: [0, 1]\n".write(
            to: dir.appendingPathComponent("f.yml"), atomically: true, encoding: .utf8)
        try info.write(to: dir.appendingPathComponent("info.yml"), atomically: true, encoding: .utf8)
        try graph.write(to: dir.appendingPathComponent("navgraph.json"), atomically: true, encoding: .utf8)
        return dir
    }

    private let info = "floor:\n    id: 1\n    features_file: f.yml\n    walls: w.bmp\n    scale: 10\n"
    private func graph(floor: String) -> String {
        "{\"nodes\": {\"1\": {\"id\": 1, \"type\": \"destination\", \"position\": [5, 5], \"floor\": \(floor), \"label\": \"kitchen\"}}, \"weights\": [[0]]}"
    }

    func testTheFolderImportsWithAnIntegerFloorNumber() throws {
        // Control: the JSON integer 1 names floor "1".
        let (b, _) = try InavigateImporter.importBuilding(from: try folder(info: info, graph: graph(floor: "1")))
        XCTAssertEqual(b.graph.nodes.map(\.floorId), ["1"])
    }

    func testAnIntegerFloorBeyondIntIsAnErrorNotATrap() throws {
        // Was: String(Int(1e20)) -> "Double value cannot be converted to Int" (fuzz target inavigate).
        let dir = try folder(info: info, graph: graph(floor: "100000000000000000000"))
        XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir)) { e in
            XCTAssertEqual("\(e)", "\(dir.appendingPathComponent("navgraph.json").path): node 1 has no 'floor'")
        }
    }

    func testAFloorNumberOffTheElevationRangeIsAnErrorNotATrap() throws {
        // Was: Int.min - 1 overflowed computing the elevation (floor id -9223372036854775808).
        for id in ["-9223372036854775808", "9223372036854775807", "252"] {
            let dir = try folder(info: info.replacingOccurrences(of: "id: 1", with: "id: \(id)"), graph: graph(floor: "\"\(id)\""))
            XCTAssertThrowsError(try InavigateImporter.importBuilding(from: dir), id) { e in
                XCTAssertTrue("\(e)".hasPrefix("\(dir.appendingPathComponent("info.yml").path): floor id '\(id)' (line 1): its elevation"), "\(e)")
            }
        }
        // Floor 251 is at 1000 m, the format's limit: accepted.
        let dir = try folder(info: info.replacingOccurrences(of: "id: 1", with: "id: 251"), graph: graph(floor: "\"251\""))
        XCTAssertEqual(try InavigateImporter.importBuilding(from: dir).building.floors.first?.elevationMeters, 1000)
    }
}
