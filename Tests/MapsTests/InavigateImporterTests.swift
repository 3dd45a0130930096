import Foundation
import XCTest
@testable import Maps

/// Converts the real Smith-Kettlewell maps in ../shared/data/skeri_inavigate (never copied into the repo).
final class InavigateImporterTests: XCTestCase {
    /// ../shared/data/skeri_inavigate relative to the package root (found from this file's path).
    static var skeriURL: URL {
        URL(fileURLWithPath: #filePath).resolvingSymlinksInPath().deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent()
            .deletingLastPathComponent().appendingPathComponent("shared/data/skeri_inavigate")
    }

    static func skeriOrSkip() throws -> URL {
        let u = skeriURL
        guard FileManager.default.fileExists(atPath: u.appendingPathComponent("floors/info.yml").path) else {
            throw XCTSkip("../shared/data/skeri_inavigate is not present")
        }
        return u
    }

    /// Number of `type: exit_sign` records in a survey file, counted independently of the importer.
    static func exitSignCount(_ url: URL) throws -> Int {
        try String(contentsOf: url, encoding: .utf8).split(separator: "\n")
            .filter { $0.trimmingCharacters(in: .whitespaces) == "type: exit_sign" }.count
    }

    func testImportsFloorsTwoToFour() throws {
        let dir = try Self.skeriOrSkip()
        let (b, report) = try InavigateImporter.importBuilding(from: dir)
        XCTAssertEqual(b.floors.map(\.id), ["2", "3", "4"])
        XCTAssertEqual(b.id, "skeri")
        // info.yml's angle_to_north 9.1 (every floor): a compass facing the plan's +y reads 360 - 9.1.
        XCTAssertEqual(b.compassHeadingOfMapNorthDeg ?? .nan, 350.9, accuracy: 1e-9)
        for r in report {
            print("SKERI floor \(r.floorId): \(r.walls) walls, \(r.signs) signs, \(r.pointsOfInterest) POIs, \(r.nodes) nodes, sign moves max \(String(format: "%.3f", r.signAdjustmentsMeters.max() ?? 0)) m")
        }
        for f in b.floors {
            // Sign count per floor equals the survey's.
            let yml = dir.appendingPathComponent("floors/mapFeatures_\(f.id).yml")
            XCTAssertEqual(f.signs.count, try Self.exitSignCount(yml), "floor \(f.id)")
            // Every wall sign on a wall after snapping (moved at most 0.5 m); signs with no wall face within
            // 0.5 m are projecting (flag / ceiling-hung), left where surveyed, within 1.5 m of a wall.
            for s in f.signs {
                let d = f.nearestWall(to: s.position)!.distanceMeters
                switch s.placement {
                case .wall:
                    XCTAssertLessThanOrEqual(d, 1e-9, s.id)
                    XCTAssertLessThanOrEqual(s.positionAdjustmentMeters ?? 0, 0.5 + 1e-9, s.id)
                case .projecting:
                    // Either half of a back-to-back pair, or a lone sign with no wall face within 0.5 m.
                    let twin = f.signs.contains { $0.id != s.id && $0.position == s.position
                        && $0.facing.x * s.facing.x + $0.facing.y * s.facing.y < -0.99 }
                    if !twin { XCTAssertGreaterThan(d, 0.5, s.id) }
                    XCTAssertLessThanOrEqual(d, 1.5, s.id)
                    XCTAssertEqual(s.positionAdjustmentMeters, 0, s.id)
                }
                XCTAssertEqual(s.facing.vectorLength, 1, accuracy: 1e-9)
                XCTAssertEqual(s.heightMeters, 0.21); XCTAssertEqual(s.widthMeters, 0.30)
                XCTAssertEqual(s.mountingHeightMeters, 2.38)
            }
            // Floor extent matches the image at its scale (floor 3: 485 x 236 px at 11.73 px/m).
            if f.id == "3" {
                XCTAssertLessThanOrEqual(f.bounds.maxX, 485 / 11.73 + 1e-9)
                XCTAssertLessThanOrEqual(f.bounds.maxY, 236 / 11.73 + 1e-9)
                XCTAssertGreaterThan(f.bounds.width, 35)
            }
            // Graph connected per floor (same-floor edges only).
            let ids = Set(b.graph.nodes.filter { $0.floorId == f.id }.map(\.id))
            XCTAssertFalse(ids.isEmpty)
            var adj: [String: [String]] = [:]
            for e in b.graph.edges where ids.contains(e.from) && ids.contains(e.to) {
                adj[e.from, default: []].append(e.to); adj[e.to, default: []].append(e.from)
            }
            var seen: Set<String> = [ids.first!]
            var stack = [ids.first!]
            while let x = stack.popLast() { for y in adj[x] ?? [] where !seen.contains(y) { seen.insert(y); stack.append(y) } }
            XCTAssertEqual(seen, ids, "floor \(f.id) graph is disconnected")
        }
        // The graph (pixels of the graph editor) and the traced walls (pixels of the mask) line up: no
        // same-floor edge passes through a wall (ends shrunk by 1 cm: door nodes may touch a wall face).
        for e in b.graph.edges where !b.isVertical(e) {
            let a = b.node(id: e.from)!.position, c = b.node(id: e.to)!.position
            let len = a.distance(to: c), ux = (c.x - a.x) / len * 0.01, uy = (c.y - a.y) / len * 0.01
            let f = b.floor(id: b.node(id: e.from)!.floorId)!
            XCTAssertFalse(f.crossesWall(from: Point2(a.x + ux, a.y + uy), to: Point2(c.x - ux, c.y - uy)), "\(e.from)-\(e.to)")
        }
        // Labelled destinations.
        XCTAssertEqual(b.pointsOfInterest(named: "Men's restroom").count, 3)
        XCTAssertEqual(b.pointsOfInterest(named: "women's restroom").count, 3)
        XCTAssertEqual(b.pointsOfInterest(named: "Elevator").count, 3)
        XCTAssertEqual(b.pointOfInterest(id: "mens-restroom-3f")?.category, "restroom")
        XCTAssertEqual(b.pointOfInterest(id: "elevator-4f")?.category, "elevator")
        XCTAssertEqual(b.pointOfInterest(named: "Verghese Lab")?.behindDoor, true)
        XCTAssertEqual(b.pointOfInterest(named: "conference room", onFloor: "4")?.id, "conference-room-4f")
        // Elevator buttons joined 2-3 and 3-4, lengths = elevation differences.
        let vertical = b.graph.edges.filter { b.isVertical($0) }
        XCTAssertEqual(vertical.count, 2)
        for e in vertical { XCTAssertEqual(b.lengthMeters(of: e), 4.0, accuracy: 1e-12) }
        // A node's pixel position converts with the floor's scale: node 27 (floor 3, men's restroom) at
        // [218.50, 26.40] px -> x = 218.50 / 11.73, y = (236 - 26.40) / 11.73.
        let n27 = try XCTUnwrap(b.node(id: "node-27"))
        XCTAssertEqual(n27.position.x, 218.5004677268475 / 11.73, accuracy: 1e-9)
        XCTAssertEqual(n27.position.y, (236 - 26.399906454630525) / 11.73, accuracy: 1e-9)
    }

    func testImportedBuildingSurvivesWriteAndLoad() throws {
        let dir = try Self.skeriOrSkip()
        let (b, _) = try InavigateImporter.importBuilding(from: dir)
        let data = try MapWriter.encode(b)
        let loaded = try MapLoader.load(data: data, fileName: "skeri.json")
        XCTAssertEqual(loaded, b)
    }
}
