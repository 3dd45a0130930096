import Foundation
import Maps

/// Errors of the simulator, each naming the input at fault.
public enum SimulationError: Error, CustomStringConvertible, Equatable {
    /// A start or destination matches no point of interest (by id or name) and no graph node.
    case unknownPlace(String)
    /// The point of interest has no node in the navigation graph.
    case placeNotInGraph(String)
    /// No path joins the two places in the navigation graph.
    case noRoute(from: String, to: String)
    /// A scenario's setting is out of range.
    case invalidScenario(String)
    /// The map named by a scenario cannot be loaded.
    case mapUnavailable(String)
    /// `wrongTurn` was asked for but the route passes no junction with a branch to take by mistake.
    case noWrongTurnPossible(String)
    /// The route itself crosses a wall (a map error: a graph edge through a wall), so no wall-free walk exists.
    case routeCrossesWall(String)

    /// Human-readable message.
    public var description: String {
        switch self {
        case .unknownPlace(let s): return "no point of interest or graph node named '\(s)'"
        case .placeNotInGraph(let s): return "point of interest '\(s)' has no node in the navigation graph"
        case .noRoute(let a, let b): return "no route from '\(a)' to '\(b)' in the navigation graph"
        case .invalidScenario(let s): return "invalid scenario: \(s)"
        case .mapUnavailable(let s): return "map unavailable: \(s)"
        case .noWrongTurnPossible(let s): return "cannot simulate a wrong turn: \(s)"
        case .routeCrossesWall(let s): return "the route crosses a wall: \(s)"
        }
    }
}

/// Shortest paths over `Building.graph` by Dijkstra's algorithm (Dijkstra 1959), edge lengths as the map
/// model defines them (horizontal distance on a floor; elevation difference between vertical-link nodes).
/// Private to the simulator so that it does not depend on the Navigation module.
struct RoutePlanner {
    let building: Building
    private let nodeIndex: [String: Int]
    /// Adjacency: for each node, (neighbor index, length in meters).
    let neighbors: [[(Int, Double)]]

    init(building: Building) {
        self.building = building
        var idx: [String: Int] = [:]
        for (i, n) in building.graph.nodes.enumerated() { idx[n.id] = i }
        nodeIndex = idx
        var adj = [[(Int, Double)]](repeating: [], count: building.graph.nodes.count)
        let elevation = Dictionary(building.floors.map { ($0.id, $0.elevationMeters) }, uniquingKeysWith: { a, _ in a })
        for e in building.graph.edges {
            guard let a = idx[e.from], let b = idx[e.to], a != b else { continue }
            let na = building.graph.nodes[a], nb = building.graph.nodes[b]
            let length: Double
            if na.floorId == nb.floorId {
                length = hypot(na.position.x - nb.position.x, na.position.y - nb.position.y)
            } else {
                length = abs((elevation[na.floorId] ?? 0) - (elevation[nb.floorId] ?? 0)) + 1.0
            }
            adj[a].append((b, length)); adj[b].append((a, length))
        }
        neighbors = adj
    }

    /// Index of a node.
    func index(of nodeId: String) -> Int? { nodeIndex[nodeId] }

    /// The graph node standing for a place given as a point-of-interest id, a point-of-interest name
    /// (case-insensitive), or a graph node id.
    func resolve(_ place: String) throws -> (nodeIndex: Int, poi: PointOfInterest?, floorId: String) {
        let nodes = building.graph.nodes
        var poi: PointOfInterest?
        for f in building.floors {
            if let p = f.pointsOfInterest.first(where: { $0.id == place }) { poi = p; break }
        }
        if poi == nil {
            let lower = place.lowercased()
            for f in building.floors {
                if let p = f.pointsOfInterest.first(where: { $0.name.lowercased() == lower }) { poi = p; break }
            }
        }
        if let p = poi {
            if let i = nodes.firstIndex(where: { $0.pointOfInterestId == p.id }) {
                return (i, p, nodes[i].floorId)
            }
            throw SimulationError.placeNotInGraph(p.id)
        }
        if let i = nodeIndex[place] { return (i, nil, nodes[i].floorId) }
        if let i = nodes.firstIndex(where: { ($0.label ?? "").lowercased() == place.lowercased() }) {
            return (i, nil, nodes[i].floorId)
        }
        throw SimulationError.unknownPlace(place)
    }

    /// Node indices of the shortest path from `a` to `b` (inclusive), nil when unreachable.
    func shortestPath(from a: Int, to b: Int) -> [Int]? {
        let n = neighbors.count
        var dist = [Double](repeating: .infinity, count: n)
        var prev = [Int](repeating: -1, count: n)
        var done = [Bool](repeating: false, count: n)
        dist[a] = 0
        // Binary heap of (distance, node).
        var heap: [(Double, Int)] = [(0, a)]
        func push(_ e: (Double, Int)) {
            heap.append(e)
            var i = heap.count - 1
            while i > 0 { let p = (i - 1) / 2; if heap[p].0 <= heap[i].0 { break }; heap.swapAt(p, i); i = p }
        }
        func pop() -> (Double, Int) {
            let top = heap[0]
            let last = heap.removeLast()
            if !heap.isEmpty {
                heap[0] = last
                var i = 0
                while true {
                    let l = 2 * i + 1, r = l + 1
                    var m = i
                    if l < heap.count && heap[l].0 < heap[m].0 { m = l }
                    if r < heap.count && heap[r].0 < heap[m].0 { m = r }
                    if m == i { break }
                    heap.swapAt(m, i); i = m
                }
            }
            return top
        }
        while !heap.isEmpty {
            let (d, u) = pop()
            if done[u] { continue }
            done[u] = true
            if u == b { break }
            for (v, w) in neighbors[u] where !done[v] && d + w < dist[v] {
                dist[v] = d + w; prev[v] = u; push((dist[v], v))
            }
        }
        guard dist[b].isFinite else { return nil }
        var path = [b]
        while path.last! != a { path.append(prev[path.last!]) }
        return path.reversed()
    }
}
