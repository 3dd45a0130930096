import Foundation
import XCTest
@testable import Maps

final class GeometryTests: XCTestCase {
    func testPointSegmentDistance() {
        let a = Point2(0, 0), b = Point2(4, 0)
        XCTAssertEqual(Geometry.distance(from: Point2(2, 3), toSegmentFrom: a, to: b), 3, accuracy: 1e-12)   // interior
        XCTAssertEqual(Geometry.distance(from: Point2(-3, 4), toSegmentFrom: a, to: b), 5, accuracy: 1e-12)  // before a
        XCTAssertEqual(Geometry.distance(from: Point2(7, -4), toSegmentFrom: a, to: b), 5, accuracy: 1e-12)  // past b
        XCTAssertEqual(Geometry.distance(from: Point2(1, 1), toSegmentFrom: a, to: a), 2.0.squareRoot(), accuracy: 1e-12)
        XCTAssertEqual(Geometry.closestPoint(to: Point2(1, 1), onSegmentFrom: Point2(0, 0), to: Point2(2, 2)), Point2(1, 1))
        XCTAssertEqual(Wall(from: a, to: b).distance(to: Point2(2, -0.5)), 0.5, accuracy: 1e-12)
    }

    func testSegmentIntersection() {
        XCTAssertTrue(Geometry.segmentsIntersect(Point2(0, 0), Point2(2, 2), Point2(0, 2), Point2(2, 0)))   // X
        XCTAssertFalse(Geometry.segmentsIntersect(Point2(0, 0), Point2(1, 1), Point2(0, 2), Point2(0.9, 1.1)))
        XCTAssertTrue(Geometry.segmentsIntersect(Point2(0, 0), Point2(1, 0), Point2(1, 0), Point2(1, 5)))   // touching end
        XCTAssertTrue(Geometry.segmentsIntersect(Point2(0, 0), Point2(3, 0), Point2(2, 0), Point2(5, 0)))   // collinear overlap
        XCTAssertFalse(Geometry.segmentsIntersect(Point2(0, 0), Point2(1, 0), Point2(2, 0), Point2(5, 0)))  // collinear apart
        XCTAssertFalse(Geometry.segmentsIntersect(Point2(0, 0), Point2(4, 0), Point2(0, 1), Point2(4, 1)))  // parallel
        let hit = Geometry.segmentIntersection(Point2(0, 1), Point2(10, 1), Point2(4, 0), Point2(4, 5))
        XCTAssertEqual(hit?.t ?? -1, 0.4, accuracy: 1e-12)
        XCTAssertEqual(hit?.point, Point2(4, 1))
        XCTAssertNil(Geometry.segmentIntersection(Point2(0, 1), Point2(3, 1), Point2(4, 0), Point2(4, 5)))
    }

    func testFloorBoundsNearestWallAndCrossing() {
        let f = MapFixtures.building().floors[0]
        XCTAssertEqual(f.bounds, Rect2(minX: 0, minY: 0, maxX: 10, maxY: 4))
        XCTAssertEqual(f.bounds.center, Point2(5, 2))
        let n = f.nearestWall(to: Point2(9, 2))!
        XCTAssertEqual(n.index, 1); XCTAssertEqual(n.distanceMeters, 1, accuracy: 1e-12)
        XCTAssertTrue(f.crossesWall(from: Point2(5, 2), to: Point2(5, 6)))
        XCTAssertFalse(f.crossesWall(from: Point2(1, 1), to: Point2(9, 3)))
        XCTAssertEqual(Floor(id: "e", name: "e", elevationMeters: 0, walls: []).bounds, Rect2(minX: 0, minY: 0, maxX: 0, maxY: 0))
    }

    func testBuildingLookupsAndEdgeLengths() throws {
        let b = MapFixtures.building()
        XCTAssertEqual(b.node(id: "c1")?.position, Point2(5, 2))
        XCTAssertNil(b.node(id: "zz"))
        XCTAssertEqual(b.pointOfInterest(id: "poi-b")?.name, "Room B")
        XCTAssertEqual(b.floor(ofPointOfInterest: "poi-b")?.id, "2")
        XCTAssertEqual(b.pointOfInterest(named: "  room a ")?.id, "poi-a")
        XCTAssertNil(b.pointOfInterest(named: "Room A", onFloor: "2"))
        XCTAssertEqual(b.pointsOfInterest(named: "ROOM B").map(\.id), ["poi-b"])
        XCTAssertEqual(b.node(forPointOfInterest: "poi-a")?.id, "a")
        // Same floor: horizontal distance; across floors: elevation difference.
        XCTAssertEqual(b.lengthMeters(of: GraphEdge(from: "a", to: "c1")), 3, accuracy: 1e-12)
        XCTAssertEqual(b.lengthMeters(of: GraphEdge(from: "e1", to: "e2")), 3.5, accuracy: 1e-12)
        XCTAssertTrue(b.isVertical(GraphEdge(from: "e1", to: "e2")))
        XCTAssertEqual(b.lengthMeters(of: GraphEdge(from: "a", to: "nowhere")), .infinity)
        XCTAssertEqual(Set(b.neighbors(of: "e1").map(\.node.id)), ["c1", "e2"])
        let c = b.counts
        XCTAssertEqual([c.floors, c.walls, c.signs, c.pointsOfInterest, c.nodes, c.edges], [2, 8, 2, 2, 6, 5])
    }
}
