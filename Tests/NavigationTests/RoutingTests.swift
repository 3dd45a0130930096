// Snapping (grid vs brute force, walls) and Dijkstra (heap vs a plain O(V^2) reference) on seeded random
// graphs, plus the graph's input errors.
import Foundation
import Maps
import XCTest
@testable import Navigation
import TestRandom

/// A jittered grid graph on one floor: `side` x `side` nodes `spacing` meters apart, each joined to its
/// right and upper neighbours with probability `keep`.
func randomGridBuilding(side: Int, spacing: Double, keep: Double, seed: UInt64) -> Building {
    var rng = SplitMix64(seed: seed)
    var nodes: [GraphNode] = []
    for j in 0..<side {
        for i in 0..<side {
            let p = Point2(x: Double(i) * spacing + (rng.unit() - 0.5) * spacing * 0.4,
                           y: Double(j) * spacing + (rng.unit() - 0.5) * spacing * 0.4)
            nodes.append(GraphNode(id: "n\(j * side + i)", kind: .control, floorId: "1", position: p))
        }
    }
    var edges: [GraphEdge] = []
    for j in 0..<side {
        for i in 0..<side {
            if i + 1 < side && rng.unit() < keep { edges.append(GraphEdge(from: "n\(j * side + i)", to: "n\(j * side + i + 1)")) }
            if j + 1 < side && rng.unit() < keep { edges.append(GraphEdge(from: "n\(j * side + i)", to: "n\((j + 1) * side + i)")) }
        }
    }
    return Building(id: "random", name: "Random", floors: [Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: [])],
                    graph: NavigationGraph(nodes: nodes, edges: edges))
}

final class RoutingTests: XCTestCase {
    func testGridSnapEqualsBruteForceNearestEdge() throws {
        let b = randomGridBuilding(side: 30, spacing: 3, keep: 0.7, seed: 42)
        let g = try RoutingGraph(building: b)
        let router = Router(graph: g)
        var rng = SplitMix64(seed: 7)
        for _ in 0..<1000 {
            // Includes points outside the graph's bounding box.
            let p = Point2(x: rng.unit() * 110 - 10, y: rng.unit() * 110 - 10)
            let snap = try XCTUnwrap(router.snap(p, floorId: "1"))
            var best = Double.infinity
            for e in 0..<g.edgeCount {
                best = min(best, projectOntoSegment(Vec2(p), g.positions[g.edgeFrom[e]], g.positions[g.edgeTo[e]]).distance)
            }
            XCTAssertEqual(snap.distanceMeters, best, accuracy: 1e-9)
            XCTAssertFalse(snap.throughWall)
        }
    }

    func testHeapDijkstraEqualsQuadraticReference() throws {
        let b = randomGridBuilding(side: 20, spacing: 3, keep: 0.75, seed: 3)
        let g = try RoutingGraph(building: b)
        let router = Router(graph: g)
        var rng = SplitMix64(seed: 11)
        var reachable = 0
        for _ in 0..<60 {
            let p = Point2(x: rng.unit() * 57, y: rng.unit() * 57)
            let dest = rng.int(g.nodeCount)
            let snap = try XCTUnwrap(router.snap(p, floorId: "1"))
            let ref = quadraticDijkstra(g, router: router, from: snap)
            let path = router.shortestPath(from: snap, to: dest)
            if ref[dest].isFinite {
                reachable += 1
                let r = try XCTUnwrap(path)
                XCTAssertEqual(r.costMeters, ref[dest], accuracy: 1e-9)
                // The path is consistent: edges join consecutive nodes and their costs add up.
                var total = snap.parameter * router.cost(ofEdge: snap.edgeIndex)
                if r.nodeIndices.first == g.edgeTo[snap.edgeIndex] {
                    total = (1 - snap.parameter) * router.cost(ofEdge: snap.edgeIndex)
                }
                for k in 1..<r.nodeIndices.count {
                    let e = r.edgeIndices[k]
                    XCTAssertEqual(Set([g.edgeFrom[e], g.edgeTo[e]]), Set([r.nodeIndices[k - 1], r.nodeIndices[k]]))
                    total += router.cost(ofEdge: e)
                }
                XCTAssertEqual(total, r.costMeters, accuracy: 1e-9)
            } else {
                XCTAssertNil(path)
            }
        }
        XCTAssertGreaterThan(reachable, 30)
    }

    /// Plain array Dijkstra, O(V^2), from the virtual start node.
    func quadraticDijkstra(_ g: RoutingGraph, router: Router, from s: SnappedPosition) -> [Double] {
        var dist = [Double](repeating: .infinity, count: g.nodeCount)
        var done = [Bool](repeating: false, count: g.nodeCount)
        var incident = [[Int]](repeating: [], count: g.nodeCount)
        for e in 0..<g.edgeCount { incident[g.edgeFrom[e]].append(e); incident[g.edgeTo[e]].append(e) }
        let c = router.cost(ofEdge: s.edgeIndex)
        dist[g.edgeFrom[s.edgeIndex]] = min(dist[g.edgeFrom[s.edgeIndex]], s.parameter * c)
        dist[g.edgeTo[s.edgeIndex]] = min(dist[g.edgeTo[s.edgeIndex]], (1 - s.parameter) * c)
        for _ in 0..<g.nodeCount {
            var v = -1
            for i in 0..<g.nodeCount where !done[i] && dist[i].isFinite && (v < 0 || dist[i] < dist[v]) { v = i }
            if v < 0 { break }
            done[v] = true
            for e in incident[v] {
                let w = g.otherEnd(ofEdge: e, from: v)
                dist[w] = min(dist[w], dist[v] + router.cost(ofEdge: e))
            }
        }
        return dist
    }

    func testSnapDoesNotGoThroughAWall() throws {
        // Corridor a-b at y = 4, a wall at y = 3, corridor c-d at y = 0 (1 m grid).
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            a-------b
            #########


            c-------d
            """).build()
        let router = Router(graph: try RoutingGraph(building: b))
        // 1.2 m from a-b through the wall, 2.8 m from c-d in the clear: c-d wins.
        let s = try XCTUnwrap(router.snap(Point2(x: 3, y: 2.8), floorId: "1"))
        XCTAssertEqual(s.point, Point2(x: 3, y: 0))
        XCTAssertFalse(s.throughWall)
        // Above the wall, a-b is both nearest and clear.
        let above = try XCTUnwrap(router.snap(Point2(x: 3, y: 3.4), floorId: "1"))
        XCTAssertEqual(above.point, Point2(x: 3, y: 4))
        // Nothing clear within the search radius: nearest edge, flagged.
        var near = RoutingOptions()
        near.maxUnobstructedSnapMeters = 2
        let r2 = Router(graph: router.graph, options: near)
        let fallback = try XCTUnwrap(r2.snap(Point2(x: 3, y: 2.8), floorId: "1"))
        XCTAssertEqual(fallback.point, Point2(x: 3, y: 4))
        XCTAssertTrue(fallback.throughWall)
    }

    func testSnapOnUnknownFloorOrEmptyFloorIsNil() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a---b").floor("2", map: "").build()
        let router = Router(graph: try RoutingGraph(building: b))
        XCTAssertNil(router.snap(Point2(x: 0, y: 0), floorId: "9"))
        XCTAssertNil(router.snap(Point2(x: 0, y: 0), floorId: "2"))
    }

    func testDoorPenaltyAndVerticalCosts() throws {
        let b = FloorPlanFixture(gridMeters: 2)
            .floor("1", map: "a-D-b---E")
            .floor("2", map: "        E")
            .build()
        let g = try RoutingGraph(building: b)
        let router = Router(graph: g)
        let ab = try XCTUnwrap((0..<g.edgeCount).first { g.edges[$0].from == "a" })
        XCTAssertEqual(router.cost(ofEdge: ab), 8 + 2, "8 m plus the 2 m door penalty")
        let ride = try XCTUnwrap((0..<g.edgeCount).first { g.kind(ofEdge: $0) == .elevator })
        XCTAssertEqual(router.cost(ofEdge: ride), 20 + 4, "20 m penalty plus 1 m per meter of the 4 m rise")
    }

    func testInvalidGraphsAreReportedByName() {
        func building(_ nodes: [GraphNode], _ edges: [GraphEdge]) -> Building {
            Building(id: "x", name: "X", floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: []),
                                                  Floor(id: "2", name: "F2", elevationMeters: 4, walls: [])],
                     graph: NavigationGraph(nodes: nodes, edges: edges))
        }
        let a = GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(0, 0))
        let b = GraphNode(id: "b", kind: .control, floorId: "2", position: Point2(0, 0))
        XCTAssertThrowsError(try RoutingGraph(building: building([a], [GraphEdge(from: "a", to: "zz")]))) {
            XCTAssertTrue("\($0)".contains("'zz'"), "\($0)")
        }
        XCTAssertThrowsError(try RoutingGraph(building: building([a, a], []))) {
            XCTAssertTrue("\($0)".contains("duplicate node id 'a'"), "\($0)")
        }
        XCTAssertThrowsError(try RoutingGraph(building: building([a, b], [GraphEdge(from: "a", to: "b")]))) {
            XCTAssertTrue("\($0)".contains("not both elevator or both stairs"), "\($0)")
        }
        let lost = GraphNode(id: "c", kind: .control, floorId: "7", position: Point2(0, 0))
        XCTAssertThrowsError(try RoutingGraph(building: building([lost], []))) {
            XCTAssertTrue("\($0)".contains("floor '7'"), "\($0)")
        }
        let fixture = FloorPlanFixture(gridMeters: 1).floor("1", map: "a---b").build()
        XCTAssertThrowsError(try Navigator(building: fixture, destinationId: "nowhere")) {
            XCTAssertEqual($0 as? NavigationError, .unknownDestination("nowhere"))
        }
    }

    func testFarFlungCoordinatesAndBadInputDoNotCrash() throws {
        // Two corridors 10,000 km apart: the grid coarsens instead of allocating 10^13 cells.
        let nodes = [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(0, 0)),
                     GraphNode(id: "b", kind: .control, floorId: "1", position: Point2(10, 0)),
                     GraphNode(id: "c", kind: .control, floorId: "1", position: Point2(1e7, 1e7)),
                     GraphNode(id: "d", kind: .control, floorId: "1", position: Point2(1e7 + 10, 1e7))]
        let b = Building(id: "far", name: "Far", floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: [])],
                         graph: NavigationGraph(nodes: nodes, edges: [GraphEdge(from: "a", to: "b"), GraphEdge(from: "c", to: "d")]))
        let router = Router(graph: try RoutingGraph(building: b))
        XCTAssertEqual(router.snap(Point2(5, 1), floorId: "1")?.point, Point2(5, 0))
        XCTAssertThrowsError(try RoutingGraph(building: b, gridCellMeters: 0))
        let nav = try Navigator(building: b, destinationId: "b")
        XCTAssertEqual(nav.update(NavigationInput(t: .nan, positionInMap: Point2(1, 0), floorId: "1", headingRad: 0, isLocalized: true)), [])
        XCTAssertEqual(nav.update(NavigationInput(t: 0, positionInMap: Point2(.infinity, 0), floorId: "1", headingRad: 0,
                                                  isLocalized: true)), [])
        XCTAssertNil(nav.currentRoute)
        XCTAssertEqual(nav.update(NavigationInput(t: 0.1, positionInMap: Point2(1, 0), floorId: "nowhere", headingRad: 0,
                                                  isLocalized: true)), [])
    }

    func testDestinationByPointOfInterestId() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a---b---c")
            .pointOfInterest(node: "c", id: "poi-312", name: "Room 312").build()
        let nav = try Navigator(building: b, destinationId: "poi-312")
        XCTAssertEqual(nav.graph.nodes[nav.destinationNode].id, "c")
        XCTAssertEqual(nav.destinationName, "Room 312")
        let byNode = try Navigator(building: b, destinationId: "c")
        XCTAssertEqual(byNode.destinationName, "Room 312", "a node linked to a point of interest speaks its name")
    }
}
