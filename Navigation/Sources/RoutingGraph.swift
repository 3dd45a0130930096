// The navigation graph compiled for routing: integer node and edge indices, adjacency in compressed rows
// (CSR), edge lengths, door and vertical-link flags, and one spatial index per floor for snapping.
// Built once per building; immutable afterwards, so it can be shared by several routers.
import Foundation
import Maps

/// How an edge is walked.
public enum EdgeKind: Sendable, Equatable {
    /// On one floor (corridor, doorway, room stub).
    case horizontal
    /// Between floors by elevator.
    case elevator
    /// Between floors by stairs.
    case stairs
}

/// The building's navigation graph in routing form (paper section 4: "the walkable area ... is described
/// by a graph whose nodes are either points of interest or control points"), plus vertical links.
public final class RoutingGraph: Sendable {
    /// The building this graph was compiled from.
    public let building: Building
    /// Node records in index order (same order as `building.graph.nodes`).
    public let nodes: [GraphNode]
    /// Edge records in index order (same order as `building.graph.edges`).
    public let edges: [GraphEdge]
    /// Index of a node by its id.
    public let nodeIndexById: [String: Int]

    let positions: [Vec2]
    /// Floor index (into `floorIds`) of each node.
    let nodeFloor: [Int]
    /// Floor ids in building order.
    let floorIds: [String]
    let floorIndexById: [String: Int]

    let edgeFrom: [Int]
    let edgeTo: [Int]
    /// Horizontal length for edges on one floor; the elevation difference for vertical edges, meters.
    let edgeLength: [Double]
    let edgeKind: [EdgeKind]
    let edgeDoor: [Bool]

    /// CSR adjacency: the neighbours of node v are `adjNode[adjStart[v] ..< adjStart[v + 1]]` reached over
    /// edge `adjEdge[...]` in the same slot.
    let adjStart: [Int]
    let adjNode: [Int32]
    let adjEdge: [Int32]

    /// Spatial index of each floor's horizontal edges and walls (same order as `floorIds`).
    let floorIndices: [FloorSpatialIndex]

    /// Number of nodes.
    public var nodeCount: Int { nodes.count }
    /// Number of edges.
    public var edgeCount: Int { edges.count }

    /// Compiles the graph of `building`. Throws `NavigationError.invalidGraph` naming the first problem:
    /// a duplicate node id, a node on a floor the building lacks, an edge naming an unknown node, or an edge
    /// between floors whose ends are not both elevator or both stairs landings.
    /// - Parameter gridCellMeters: cell size of the per-floor uniform grids used for snapping (2 m: about one
    ///   corridor width, so a query touches a handful of edges).
    public init(building: Building, gridCellMeters: Double = 2.0) throws {
        guard gridCellMeters.isFinite, gridCellMeters > 0 else {
            throw NavigationError.invalidGraph("grid cell size must be a positive number of meters, got \(gridCellMeters)")
        }
        self.building = building
        nodes = building.graph.nodes
        edges = building.graph.edges
        floorIds = building.floors.map(\.id)
        var floorIndexById: [String: Int] = [:]
        for (i, f) in building.floors.enumerated() {
            if floorIndexById[f.id] != nil { throw NavigationError.invalidGraph("duplicate floor id '\(f.id)'") }
            floorIndexById[f.id] = i
        }
        self.floorIndexById = floorIndexById

        var byId: [String: Int] = [:]
        var positions: [Vec2] = []
        var nodeFloor: [Int] = []
        positions.reserveCapacity(nodes.count)
        nodeFloor.reserveCapacity(nodes.count)
        for (i, n) in nodes.enumerated() {
            if byId[n.id] != nil { throw NavigationError.invalidGraph("duplicate node id '\(n.id)'") }
            guard let f = floorIndexById[n.floorId] else {
                throw NavigationError.invalidGraph("node '\(n.id)' is on floor '\(n.floorId)', which the building lacks")
            }
            guard n.position.x.isFinite, n.position.y.isFinite else {
                throw NavigationError.invalidGraph("node '\(n.id)' has a non-finite position")
            }
            byId[n.id] = i
            positions.append(Vec2(n.position))
            nodeFloor.append(f)
        }
        nodeIndexById = byId
        self.positions = positions
        self.nodeFloor = nodeFloor

        let floorElevation = building.floors.map(\.elevationMeters)
        var from: [Int] = [], to: [Int] = [], length: [Double] = [], kind: [EdgeKind] = [], door: [Bool] = []
        var degree = [Int](repeating: 0, count: nodes.count)
        for (ei, e) in edges.enumerated() {
            guard let a = byId[e.from] else {
                throw NavigationError.invalidGraph("edge \(ei) (\(e.from)-\(e.to)) names unknown node '\(e.from)'")
            }
            guard let b = byId[e.to] else {
                throw NavigationError.invalidGraph("edge \(ei) (\(e.from)-\(e.to)) names unknown node '\(e.to)'")
            }
            if a == b { throw NavigationError.invalidGraph("edge \(ei) joins node '\(e.from)' to itself") }
            from.append(a); to.append(b); door.append(e.throughDoor)
            if nodeFloor[a] == nodeFloor[b] {
                kind.append(.horizontal)
                length.append(positions[a].distance(to: positions[b]))
            } else {
                let la = nodes[a].verticalLink, lb = nodes[b].verticalLink
                guard let la, let lb, la == lb else {
                    throw NavigationError.invalidGraph(
                        "edge \(ei) joins floors '\(nodes[a].floorId)' and '\(nodes[b].floorId)' but '\(e.from)' and "
                            + "'\(e.to)' are not both elevator or both stairs landings")
                }
                kind.append(la == .elevator ? .elevator : .stairs)
                length.append(abs(floorElevation[nodeFloor[a]] - floorElevation[nodeFloor[b]]))
            }
            degree[a] += 1; degree[b] += 1
        }
        edgeFrom = from; edgeTo = to; edgeLength = length; edgeKind = kind; edgeDoor = door

        var start = [Int](repeating: 0, count: nodes.count + 1)
        for v in 0..<nodes.count { start[v + 1] = start[v] + degree[v] }
        var fill = start
        var adjNode = [Int32](repeating: 0, count: start[nodes.count])
        var adjEdge = [Int32](repeating: 0, count: start[nodes.count])
        for e in 0..<from.count {
            adjNode[fill[from[e]]] = Int32(to[e]); adjEdge[fill[from[e]]] = Int32(e); fill[from[e]] += 1
            adjNode[fill[to[e]]] = Int32(from[e]); adjEdge[fill[to[e]]] = Int32(e); fill[to[e]] += 1
        }
        adjStart = start
        self.adjNode = adjNode
        self.adjEdge = adjEdge

        var indices: [FloorSpatialIndex] = []
        for (fi, floor) in building.floors.enumerated() {
            var segs: [(Vec2, Vec2)] = [], ids: [Int] = []
            for e in 0..<from.count where kind[e] == .horizontal && nodeFloor[from[e]] == fi {
                segs.append((positions[from[e]], positions[to[e]])); ids.append(e)
            }
            // Walls with a non-finite end cannot block anything measurable: left out.
            let walls = floor.walls.filter { $0.from.x.isFinite && $0.from.y.isFinite && $0.to.x.isFinite && $0.to.y.isFinite }
                .map { (Vec2($0.from), Vec2($0.to)) }
            indices.append(FloorSpatialIndex(edgeSegments: segs, edgeIds: ids, walls: walls, cellMeters: gridCellMeters))
        }
        floorIndices = indices
    }

    /// Index of the node with this id.
    public func nodeIndex(id: String) -> Int? { nodeIndexById[id] }

    /// Position of node `index`, meters in its floor's frame.
    public func position(ofNode index: Int) -> Point2 { positions[index].point2 }

    /// Floor id of node `index`.
    public func floorId(ofNode index: Int) -> String { nodes[index].floorId }

    /// The edge's kind (horizontal, elevator, stairs).
    public func kind(ofEdge index: Int) -> EdgeKind { edgeKind[index] }

    /// The other end of edge `e` seen from node `v`.
    func otherEnd(ofEdge e: Int, from v: Int) -> Int { edgeFrom[e] == v ? edgeTo[e] : edgeFrom[e] }

    /// True when the segment between two points of one floor crosses none of that floor's walls.
    public func isUnobstructed(from a: Point2, to b: Point2, floorId: String) -> Bool {
        guard let f = floorIndexById[floorId] else { return true }
        return !floorIndices[f].walls.crosses(Vec2(a), Vec2(b))
    }
}
