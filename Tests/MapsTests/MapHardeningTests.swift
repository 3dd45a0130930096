import Foundation
import XCTest
@testable import Maps
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif

/// Hostile and damaged maps (issue 14): each case once crashed, hung, passed silently or gave a wrong reason.
/// Every assertion checks the one error's JSON path and reason.
final class MapHardeningTests: XCTestCase {
    // MARK: numbers beyond 2^63 in error messages (used to trap in MapValidator.fmt)

    func testElevationOf1e19IsReportedNotTrapped() {
        // The issue's reproducer, verbatim.
        let text = #"{"formatVersion":1,"id":"b","name":"B","floors":[{"id":"1","name":"F","elevationMeters":1e19,"walls":[{"from":[0,0],"to":[1,0]}]}],"graph":{"nodes":[{"id":"n","kind":"control","floorId":"1","position":[0,1]}],"edges":[]}}"#
        assertRejects(text, path: "$.floors[0].elevationMeters", reason: "elevation (meters) 1e+19 is out of range [-1000, 1000]")
    }

    func testHugeValuesInEveryRangeCheckedFieldAreReported() throws {
        try assertRejects(damage: { $0.floors[1].signs[0].widthMeters = 1e23 }, path: "$.floors[1].signs[0].widthMeters",
                          reason: "sign size 1e+23 m is out of range (0, 5] m")
        try assertRejects(damage: { $0.floors[0].doors[0].widthMeters = -9.3e18 }, path: "$.floors[0].doors[0].widthMeters",
                          reason: "door width must be a positive number of meters, got -9.3e+18")
        try assertRejects(damage: { $0.floors[0].signs[0].mountingHeightMeters = 1.7976931348623157e308 },
                          path: "$.floors[0].signs[0].mountingHeightMeters", reason: "1.7976931348623157e+308 is out of range")
        try assertRejects(damage: { $0.floors[0].walls[0].from.x = -9.223372036854775808e18 }, path: "$.floors[0].walls[0].from[0]",
                          reason: "coordinate x (meters) -9.223372036854776e+18 is out of range [-100000, 100000]")
    }

    func testNumberFormattingNeverTraps() {
        XCTAssertEqual(MapValidator.fmt(9_223_372_036_854_775_807.0), "9.223372036854776e+18")
        XCTAssertEqual(MapValidator.fmt(-Double.greatestFiniteMagnitude), "-1.7976931348623157e+308")
        XCTAssertEqual(MapValidator.fmt(.infinity), "inf")
        XCTAssertEqual(MapValidator.fmt(123_456_789_012.0), "123456789012")
        XCTAssertEqual(MapValidator.fmt(0.30049), "0.3")
        XCTAssertEqual(MapValidator.fmt(2.5), "2.5")
        XCTAssertEqual(MapValidator.fmt(-1000), "-1000")
    }

    // MARK: graph edges through walls (one rule: Floor.firstWallCrossed, used by the validator and the simulator)

    func testEdgeThroughAWallIsRejected() throws {
        // A partition across the ground-floor room between c1 (5, 2) and the elevator node e1 (8, 2).
        try assertRejects(damage: { $0.floors[0].walls.append(Wall(from: Point2(6.5, 0), to: Point2(6.5, 4))) },
                          path: "$.graph.edges[1]",
                          reason: "edge from \"c1\" to \"e1\" crosses or touches the wall $.floors[0].walls[4] (from [6.5, 0] to [6.5, 4])")
    }

    func testEdgeTouchingAWallEndIsRejected() throws {
        // A stub wall whose end lies exactly on the edge a (2, 2) - c1 (5, 2): touching counts.
        try assertRejects(damage: { $0.floors[0].walls.append(Wall(from: Point2(3, 2), to: Point2(3, 3))) },
                          path: "$.graph.edges[0]", reason: "crosses or touches the wall $.floors[0].walls[4]")
    }

    func testEdgeBesideAWallAndVerticalEdgesPass() throws {
        var b = MapFixtures.building()
        b.floors[0].walls.append(Wall(from: Point2(3, 2.01), to: Point2(3, 3)))   // 1 cm clear of the edge
        XCTAssertNoThrow(try MapValidator.validate(b))
        XCTAssertNil(b.floors[0].firstWallCrossed(from: Point2(2, 2), to: Point2(5, 2)))
        XCTAssertEqual(b.floors[0].firstWallCrossed(from: Point2(2, 2), to: Point2(3, 2.5)), 4)
    }

    // MARK: points of interest inside or against a wall, or behind one

    func testPointOfInterestOnAWallIsRejected() throws {
        // poi-a moved onto the west wall (x = 0); its node stays in the room.
        try assertRejects(damage: { $0.floors[0].pointsOfInterest[0].position = Point2(0.05, 2) },
                          path: "$.floors[0].pointsOfInterest[0].position",
                          reason: "point of interest \"poi-a\" is inside or against a wall: the wall $.floors[0].walls[3] is 0.05 m away (at least 0.2 m needed")
    }

    func testPointOfInterestInsideAThickWallIsRejected() throws {
        // A 2 m x 1.3 m solid block (four faces) north of node a; poi-a placed inside it, 0.65 m from its faces.
        try assertRejects(damage: { b in
            b.floors[0].walls += [Wall(from: Point2(1, 2.5), to: Point2(3, 2.5)), Wall(from: Point2(3, 2.5), to: Point2(3, 3.8)),
                                  Wall(from: Point2(3, 3.8), to: Point2(1, 3.8)), Wall(from: Point2(1, 3.8), to: Point2(1, 2.5))]
            b.floors[0].pointsOfInterest[0].position = Point2(2, 3.15)
        }, path: "$.floors[0].pointsOfInterest[0].position",
           reason: "point of interest \"poi-a\" cannot be reached from its graph node \"a\": the straight line between them crosses the wall $.floors[0].walls[4]")
    }

    func testPointOfInterestNodeInsideAWallIsRejectedByItsEdge() throws {
        // Node and point of interest both inside the block: the node's edge to the corridor crosses a face.
        try assertRejects(damage: { b in
            b.floors[0].walls += [Wall(from: Point2(1, 1), to: Point2(3, 1)), Wall(from: Point2(3, 1), to: Point2(3, 3)),
                                  Wall(from: Point2(3, 3), to: Point2(1, 3)), Wall(from: Point2(1, 3), to: Point2(1, 1))]
        }, path: "$.graph.edges[0]", reason: "edge from \"a\" to \"c1\" crosses or touches the wall $.floors[0].walls[5]")
    }

    // MARK: identifiers (a documented character set and length)

    func testScriptInAFloorIdIsRejected() throws {
        try assertRejects(damage: { b in
            let hostile = "2');document.title='PWNED';//"
            b.floors[1].id = hostile
            for i in b.graph.nodes.indices where b.graph.nodes[i].floorId == "2" { b.graph.nodes[i].floorId = hostile }
        }, path: "$.floors[1].id", reason: "identifier contains the character U+0027 (') at position 2; identifiers may use only A-Z a-z 0-9 . _ : -")
    }

    func testIdentifierCharacterSetAndLength() throws {
        try assertRejects(damage: { $0.floors[0].signs[0].id = "exit sign" }, path: "$.floors[0].signs[0].id",
                          reason: "the character U+0020 at position 5")
        try assertRejects(damage: { $0.floors[0].doors[0].id = "d\u{7}" }, path: "$.floors[0].doors[0].id",
                          reason: "the character U+0007 at position 2")
        try assertRejects(damage: { $0.id = "café" }, path: "$.id", reason: "the character U+00E9 at position 4")
        try assertRejects(damage: { $0.graph.nodes[1].id = String(repeating: "n", count: 65) }, path: "$.graph.nodes[1].id",
                          reason: "identifier is 65 characters long; at most 64 are allowed")
        var b = MapFixtures.building()
        b.id = "A.b_c:d-9"
        b.graph.nodes[1].id = String(repeating: "n", count: 64)
        b.graph.edges[0].to = b.graph.nodes[1].id
        b.graph.edges[1].from = b.graph.nodes[1].id
        XCTAssertNoThrow(try MapValidator.validate(b), "every allowed character and the longest id pass")
    }

    // MARK: floor extent: the validator applies the localizer core's limit first

    func testFloorWiderThan100KilometersIsRejected() throws {
        // Each coordinate is within +-100 km, but the floor spans 120 km.
        try assertRejects(damage: { b in
            b.floors[0].walls += [Wall(from: Point2(-60_000, 0), to: Point2(-59_999, 0)), Wall(from: Point2(60_000, 0), to: Point2(60_001, 0))]
        }, path: "$.floors[0]", reason: "floor \"1\" spans 120001 m x 4 m (x from -60000 to 60001, y from 0 to 4, over its walls, doors, signs, points of interest and graph nodes); at most 100000 m (100 km)")
    }

    func testGraphNodesCountInTheFloorExtent() throws {
        // A node 100 km east of the floor's only wall (the core's flood fill seeds there) makes it 100.005 km wide.
        try assertRejects(damage: { b in
            b.graph.nodes.append(GraphNode(id: "far", kind: .control, floorId: "1", position: Point2(100_000, 2)))
            b.graph.edges.append(GraphEdge(from: "c1", to: "far"))
            b.floors[0].walls = [Wall(from: Point2(-5, 0), to: Point2(-5, 4))]
            b.floors[0].signs = []
            b.floors[0].doors[0].position = Point2(1, 2)
        }, path: "$.floors[0]", reason: "floor \"1\" spans 100005 m x 4 m (x from -5 to 100000")
        var b = MapFixtures.building()
        b.floors[0].walls.append(Wall(from: Point2(99_990, 0), to: Point2(99_999, 0)))
        XCTAssertNoThrow(try MapValidator.validate(b), "99.999 km wide is within the limit")
    }

    // MARK: reading the file: the real reason, never a hang

    private func temporaryDirectory() throws -> URL {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("maps-hardening-\(UUID().uuidString)")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        addTeardownBlock { try? FileManager.default.removeItem(at: dir) }
        return dir
    }

    private func assertLoadFails(_ url: URL, reason: String, file: StaticString = #filePath, line: UInt = #line) {
        let start = Date()
        XCTAssertThrowsError(try MapLoader.load(contentsOf: url), file: file, line: line) { e in
            guard let m = e as? MapError else { return XCTFail("expected MapError, got \(e)", file: file, line: line) }
            XCTAssertEqual(m.file, url.lastPathComponent, file: file, line: line)
            XCTAssertEqual(m.jsonPath, "$", file: file, line: line)
            XCTAssertTrue(m.reason.contains(reason), "reason \"\(m.reason)\" lacks \"\(reason)\"", file: file, line: line)
            XCTAssertFalse(m.reason.contains("permission"), "\(m)", file: file, line: line)
        }
        XCTAssertLessThan(Date().timeIntervalSince(start), 5, "refused at once, not read", file: file, line: line)
    }

    func testFIFOIsRefusedWithoutBlocking() throws {
        let fifo = try temporaryDirectory().appendingPathComponent("pipe.json")
        XCTAssertEqual(mkfifo(fifo.path, 0o644), 0)
        // No writer ever opens the FIFO: a blocking open or read would hang here.
        assertLoadFails(fifo, reason: "not a regular file (it is a FIFO (named pipe)); a map must be a regular JSON file")
    }

    func testDevZeroIsRefused() {
        assertLoadFails(URL(fileURLWithPath: "/dev/zero"), reason: "not a regular file (it is a character device)")
    }

    func testDirectoryIsRefused() throws {
        let dir = try temporaryDirectory().appendingPathComponent("maps.json")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        assertLoadFails(dir, reason: "not a regular file (it is a directory)")
    }

    func testSymbolicLinkLoopAndDanglingLink() throws {
        let dir = try temporaryDirectory()
        let a = dir.appendingPathComponent("a.json"), b = dir.appendingPathComponent("b.json")
        try FileManager.default.createSymbolicLink(atPath: a.path, withDestinationPath: b.path)
        try FileManager.default.createSymbolicLink(atPath: b.path, withDestinationPath: a.path)
        assertLoadFails(a, reason: "too many levels of symbolic links (a symbolic-link loop): \(a.path)")
        let dangling = dir.appendingPathComponent("dangling.json")
        try FileManager.default.createSymbolicLink(atPath: dangling.path, withDestinationPath: dir.appendingPathComponent("gone.json").path)
        assertLoadFails(dangling, reason: "the file is a symbolic link to a file that does not exist")
        // A link to a good map is followed.
        let good = dir.appendingPathComponent("good.json"), link = dir.appendingPathComponent("link.json")
        try MapWriter.write(MapFixtures.building(), to: good)
        try FileManager.default.createSymbolicLink(atPath: link.path, withDestinationPath: good.path)
        XCTAssertEqual(try MapLoader.load(contentsOf: link), MapFixtures.building())
    }

    func testUnreadableFileSaysPermissionDenied() throws {
        guard getuid() != 0 else { throw XCTSkip("root reads every file") }
        let f = try temporaryDirectory().appendingPathComponent("secret.json")
        try MapWriter.write(MapFixtures.building(), to: f)
        XCTAssertEqual(chmod(f.path, 0), 0)
        XCTAssertThrowsError(try MapLoader.load(contentsOf: f)) { e in
            XCTAssertTrue((e as? MapError)?.reason.contains("permission denied") ?? false, "\(e)")
        }
    }

    func testFileOverTheSizeLimitIsRefusedUnread() throws {
        let f = try temporaryDirectory().appendingPathComponent("huge.json")
        XCTAssertTrue(FileManager.default.createFile(atPath: f.path, contents: Data("{".utf8)))
        // Sparse: 65 MiB of size, no disk blocks.
        XCTAssertEqual(truncate(f.path, off_t(MapLoader.maximumFileBytes + (1 << 20))), 0)
        assertLoadFails(f, reason: "the file is \(MapLoader.maximumFileBytes + (1 << 20)) bytes; map files are limited to \(MapLoader.maximumFileBytes) bytes (64 MiB)")
    }
}
