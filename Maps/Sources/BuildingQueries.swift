import Foundation

// Look-ups and derived values on a Building: nodes and points of interest by id or name, and derived
// edge lengths. Linear scans: buildings have at most a few thousand nodes; callers on a hot path should
// build their own index (e.g. a dictionary from `graph.nodes`).

extension Building {
    /// The graph node with this id.
    public func node(id nodeId: String) -> GraphNode? { graph.nodes.first { $0.id == nodeId } }

    /// The point of interest with this id, on any floor.
    public func pointOfInterest(id poiId: String) -> PointOfInterest? {
        for f in floors { if let p = f.pointOfInterest(id: poiId) { return p } }
        return nil
    }

    /// The first point of interest, in floor order, whose id is `key` or whose name equals `key` ignoring
    /// case, with its floor id: how the traveler's start and destination are looked up (by id from a
    /// picker or a recorded session, by name from the command line).
    public func pointOfInterest(idOrName key: String) -> (poi: PointOfInterest, floorId: String)? {
        let lowered = key.lowercased()
        for f in floors {
            if let p = f.pointsOfInterest.first(where: { $0.id == key || $0.name.lowercased() == lowered }) { return (p, f.id) }
        }
        return nil
    }

    /// The floor holding the point of interest with this id.
    public func floor(ofPointOfInterest poiId: String) -> Floor? {
        floors.first { $0.pointOfInterest(id: poiId) != nil }
    }

    /// Every point of interest whose name equals `name` ignoring case and surrounding spaces, in floor
    /// order (several floors often have a "Men's restroom").
    public func pointsOfInterest(named name: String) -> [PointOfInterest] {
        let key = Building.nameKey(name)
        return floors.flatMap { f in f.pointsOfInterest.filter { Building.nameKey($0.name) == key } }
    }

    /// The first point of interest named `name` (case-insensitive), optionally only on floor `floorId`.
    public func pointOfInterest(named name: String, onFloor floorId: String? = nil) -> PointOfInterest? {
        let key = Building.nameKey(name)
        for f in floors where floorId == nil || f.id == floorId {
            if let p = f.pointsOfInterest.first(where: { Building.nameKey($0.name) == key }) { return p }
        }
        return nil
    }

    /// The graph node standing for the point of interest `poiId` (its first one when several).
    public func node(forPointOfInterest poiId: String) -> GraphNode? {
        graph.nodes.first { $0.kind == .pointOfInterest && $0.pointOfInterestId == poiId }
    }

    /// True when the edge joins nodes on two different floors (a ride or a climb).
    public func isVertical(_ edge: GraphEdge) -> Bool {
        guard let a = node(id: edge.from), let b = node(id: edge.to) else { return false }
        return a.floorId != b.floorId
    }

    /// Derived length of an edge, meters: the horizontal distance between its nodes when both are on one
    /// floor; |elevation difference| between the floors for an edge between vertical-link nodes on
    /// different floors (any elevator/stairs time penalty is the router's business). `.infinity` when an
    /// end node or floor is unknown (impossible in a building that passed `MapValidator`).
    public func lengthMeters(of edge: GraphEdge) -> Double {
        guard let a = node(id: edge.from), let b = node(id: edge.to) else { return .infinity }
        return lengthMeters(between: a, and: b)
    }

    /// Length of an edge between nodes `a` and `b` (see `lengthMeters(of:)`), meters.
    public func lengthMeters(between a: GraphNode, and b: GraphNode) -> Double {
        if a.floorId == b.floorId { return a.position.distance(to: b.position) }
        guard let fa = floor(id: a.floorId), let fb = floor(id: b.floorId) else { return .infinity }
        return abs(fa.elevationMeters - fb.elevationMeters)
    }

    /// The edges incident to node `nodeId`, each with the node at its other end.
    public func neighbors(of nodeId: String) -> [(edge: GraphEdge, node: GraphNode)] {
        graph.edges.compactMap { e in
            let other: String
            if e.from == nodeId { other = e.to } else if e.to == nodeId { other = e.from } else { return nil }
            return node(id: other).map { (edge: e, node: $0) }
        }
    }

    /// Total counts, for summaries: floors, walls, signs, points of interest, nodes, edges.
    public var counts: (floors: Int, walls: Int, signs: Int, pointsOfInterest: Int, nodes: Int, edges: Int) {
        (floors.count, floors.reduce(0) { $0 + $1.walls.count }, floors.reduce(0) { $0 + $1.signs.count },
         floors.reduce(0) { $0 + $1.pointsOfInterest.count }, graph.nodes.count, graph.edges.count)
    }

    static func nameKey(_ s: String) -> String {
        s.trimmingCharacters(in: .whitespacesAndNewlines).lowercased()
    }
}
