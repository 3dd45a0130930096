// Routes between labelled destinations of the real Smith-Kettlewell floors (imported from
// ../shared/data/skeri_inavigate by Maps' iNavigate importer; read at test time, never copied), walked end
// to end with the cue checks of `walkRouteCheckingCues`.
import Foundation
import Maps
import XCTest
@testable import Navigation

final class SkeriRouteTests: XCTestCase {
    static func skeriBuilding() throws -> Building {
        let dir = URL(fileURLWithPath: #filePath).resolvingSymlinksInPath()
            .deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent()
            .appendingPathComponent("shared/data/skeri_inavigate")
        guard FileManager.default.fileExists(atPath: dir.appendingPathComponent("floors/info.yml").path) else {
            throw XCTSkip("../shared/data/skeri_inavigate is not present")
        }
        return try InavigateImporter.importBuilding(from: dir).building
    }

    private func node(_ b: Building, poi: String) throws -> GraphNode {
        try XCTUnwrap(b.graph.nodes.first { $0.pointOfInterestId == poi }, poi)
    }

    func testSameFloorMensRestroomToDemoRoom() throws {
        let b = try Self.skeriBuilding()
        let start = try node(b, poi: "mens-restroom-4f")
        let nav = try Navigator(building: b, destinationId: "demo-room-4f")
        let w = try walkRouteCheckingCues(nav, start: start.position, floorId: start.floorId)
        XCTAssertTrue(w.spoken.last?.hasPrefix("Arrived. Demo room is ") ?? false, "\(w.spoken)")
        XCTAssertFalse(kindsList(nav.lastManeuvers).contains("take"), kindsList(nav.lastManeuvers))
    }

    func testLibraryOnFloor2ToHapticsLabOnFloor4ByElevator() throws {
        let b = try Self.skeriBuilding()
        let start = try node(b, poi: "library-2f")
        let nav = try Navigator(building: b, destinationId: "haptics-lab-4f")
        let w = try walkRouteCheckingCues(nav, start: start.position, floorId: start.floorId)
        let kinds = kindsList(nav.lastManeuvers)
        XCTAssertTrue(kinds.contains("takeElevator,continue"), kinds)
        XCTAssertEqual(nav.lastManeuvers.first { $0.kind == .takeElevator }?.toFloorId, "4")
        XCTAssertTrue(w.spoken.contains("Take the elevator to Floor 4."), "\(w.spoken)")
        let arrival = try XCTUnwrap(w.spoken.last)
        XCTAssertTrue(arrival.hasPrefix("Arrived. Haptics lab is "), arrival)
        XCTAssertTrue(arrival.hasSuffix(", behind a door."), arrival)
    }
}
