// Snapping and shortest paths (paper section 4: "we first snap the location (x, y) to the closest point
// (x', y') on the graph ... Next we use a standard Dijkstra shortest-path algorithm").
import Foundation
import Maps

/// Edge costs and restrictions for routing. Costs are in meters of level walking, so a penalty reads as
/// "how much farther the traveler would rather walk than take this".
public struct RoutingOptions: Sendable, Equatable {
    /// Never use stairs (e.g. wheelchair users). Strict: no route rather than a route with stairs.
    public var avoidStairs = false
    /// Never use elevators. Strict, like `avoidStairs`.
    public var avoidElevators = false
    /// Fixed cost of taking an elevator: waiting for the car and finding the button (~15 s at 1.2 m/s
    /// plus margin), meters. Default 20.
    public var elevatorPenaltyMeters = 20.0
    /// Elevator cost per meter of floor-to-floor rise, meters. Default 1 (the car is about as fast as walking).
    public var elevatorMetersPerMeterOfRise = 1.0
    /// Fixed cost of taking stairs: finding the handrail and the first step, meters. Default 5.
    public var stairsPenaltyMeters = 5.0
    /// Stairs cost per meter of rise, meters. Default 4: a flight rising 1 m has about 2 m of run, walked at
    /// about half the level speed.
    public var stairsMetersPerMeterOfRise = 4.0
    /// Extra cost of passing through a door (finding and opening it without sight), meters. Default 2.
    public var doorPenaltyMeters = 2.0
    /// Snapping: how far to look for an edge reachable without crossing a wall before falling back to the
    /// nearest edge through the wall, meters. Default 10.
    public var maxUnobstructedSnapMeters = 10.0
    /// Creates the defaults above.
    public init() {}
}

/// A location estimate snapped onto the graph: a point on one horizontal edge.
public struct SnappedPosition: Sendable, Equatable {
    /// Graph edge index (into `RoutingGraph.edges`).
    public var edgeIndex: Int
    /// Position along the edge, 0 at its `from` node, 1 at its `to` node.
    public var parameter: Double
    /// The snapped point, meters in the floor's frame.
    public var point: Point2
    /// Floor of the edge.
    public var floorId: String
    /// Distance from the estimate to the snapped point, meters.
    public var distanceMeters: Double
    /// True when every edge within `maxUnobstructedSnapMeters` is behind a wall and the nearest one was
    /// used anyway.
    public var throughWall: Bool

    /// Creates a snapped position (normally made by `Router.snap`; public for tools and baselines).
    public init(edgeIndex: Int, parameter: Double, point: Point2, floorId: String, distanceMeters: Double,
                throughWall: Bool) {
        self.edgeIndex = edgeIndex; self.parameter = parameter; self.point = point; self.floorId = floorId
        self.distanceMeters = distanceMeters; self.throughWall = throughWall
    }
}

/// A shortest path from a snapped position to a node.
public struct PathResult: Sendable, Equatable {
    /// The start.
    public var start: SnappedPosition
    /// Node indices from the first node reached from the snapped point to the destination.
    public var nodeIndices: [Int]
    /// Edge indices: the first is the snapped edge when the path leaves the virtual start node through it,
    /// then one edge per consecutive pair of `nodeIndices`.
    public var edgeIndices: [Int]
    /// Total routing cost (meters, with penalties).
    public var costMeters: Double
}

/// Snaps and routes on one `RoutingGraph` with one set of options. Holds reusable scratch arrays, so a
/// query allocates only its result; not thread-safe (use one router per thread).
public final class Router {
    /// The graph routed on.
    public let graph: RoutingGraph
    /// Costs and restrictions in force.
    public let options: RoutingOptions
    /// Cost of each edge walked on its own under `options` (a ride including its fixed penalty);
    /// +infinity for an excluded edge.
    let edgeCost: [Double]
    /// Vertical edges: the per-rise part of the cost (the fixed penalty is paid once per ride, on
    /// boarding, however many floors the ride spans); +infinity when excluded. Horizontal edges: unused.
    let rideCost: [Double]
    /// Vertical edges: the fixed penalty paid on boarding.
    let boardingPenalty: [Double]

    // Dijkstra runs on states 2v (at node v on its floor) and 2v + 1 (at v inside a ride, i.e. arrived
    // by a vertical edge), so that a ride over several floors pays the elevator/stairs penalty once.
    private var dist: [Double]
    private var prevEdge: [Int32]
    private var prevState: [Int32]
    private var settled: [Bool]
    private var touched: [Int] = []
    private var heap = MinHeap()

    /// Creates a router; computes every edge's cost once.
    public init(graph: RoutingGraph, options: RoutingOptions = RoutingOptions()) {
        self.graph = graph
        self.options = options
        var cost = [Double](repeating: 0, count: graph.edgeCount)
        var ride = [Double](repeating: .infinity, count: graph.edgeCount)
        var penalty = [Double](repeating: 0, count: graph.edgeCount)
        for e in 0..<graph.edgeCount {
            let len = graph.edgeLength[e]
            switch graph.edgeKind[e] {
            case .horizontal:
                cost[e] = len + (graph.edgeDoor[e] ? options.doorPenaltyMeters : 0)
            case .elevator:
                ride[e] = options.avoidElevators ? .infinity : options.elevatorMetersPerMeterOfRise * len
                penalty[e] = options.elevatorPenaltyMeters
                cost[e] = ride[e] + penalty[e]
            case .stairs:
                ride[e] = options.avoidStairs ? .infinity : options.stairsMetersPerMeterOfRise * len
                penalty[e] = options.stairsPenaltyMeters
                cost[e] = ride[e] + penalty[e]
            }
        }
        edgeCost = cost
        rideCost = ride
        boardingPenalty = penalty
        dist = [Double](repeating: .infinity, count: 2 * graph.nodeCount)
        prevEdge = [Int32](repeating: -1, count: 2 * graph.nodeCount)
        prevState = [Int32](repeating: -1, count: 2 * graph.nodeCount)
        settled = [Bool](repeating: false, count: 2 * graph.nodeCount)
    }

    /// Cost of edge `index` walked on its own under this router's options (meters; a ride includes its
    /// fixed penalty; +infinity when excluded).
    public func cost(ofEdge index: Int) -> Double { edgeCost[index] }

    /// Cost of edge `index` as part of a route: a vertical edge that continues a ride (the previous edge
    /// was vertical too) does not pay the boarding penalty again.
    public func cost(ofEdge index: Int, continuingRide: Bool) -> Double {
        graph.edgeKind[index] != .horizontal && continuingRide ? rideCost[index] : edgeCost[index]
    }

    /// Snaps a location estimate to the nearest point of a horizontal edge on `floorId` that can be reached
    /// in a straight line without crossing a wall (falling back to the nearest edge at all, flagged
    /// `throughWall`). Uses the floor's edge grid: cost independent of the map's size. Nil when the floor
    /// is unknown or has no edges.
    public func snap(_ point: Point2, floorId: String) -> SnappedPosition? {
        guard let f = graph.floorIndexById[floorId] else { return nil }
        let index = graph.floorIndices[f]
        guard let hit = index.nearestEdge(to: Vec2(point), maxClearSearchMeters: options.maxUnobstructedSnapMeters)
        else { return nil }
        return SnappedPosition(edgeIndex: index.edgeIds[hit.segment], parameter: hit.t, point: hit.point.point2,
                               floorId: floorId, distanceMeters: hit.distance, throughWall: hit.obstructed)
    }

    /// Dijkstra with a binary heap (lazy deletion) from the snapped point, treated as a virtual node joined
    /// to both ends of its edge, to node `destination`. Stops when the destination is settled. Nil when
    /// the destination cannot be reached under the options. A ride over several floors pays its boarding
    /// penalty once (search states: at a node, or at a node inside a ride). Scratch arrays are reused and
    /// only the states touched by the previous query are reset, so a query costs O(explored log explored).
    public func shortestPath(from start: SnappedPosition, to destination: Int) -> PathResult? {
        guard destination >= 0, destination < graph.nodeCount, start.edgeIndex >= 0, start.edgeIndex < graph.edgeCount
        else { return nil }
        let e0 = start.edgeIndex
        let a = graph.edgeFrom[e0], b = graph.edgeTo[e0]
        let c0 = edgeCost[e0]
        guard c0.isFinite, graph.edgeKind[e0] == .horizontal else { return nil }
        // Work on local copies of the scratch state (moved out of the object, so no copy and no
        // per-access exclusivity checks in the loop), moved back at the end.
        var dist = self.dist, prevEdge = self.prevEdge, prevState = self.prevState, settled = self.settled
        var touched = self.touched, heap = self.heap
        self.dist = []; self.prevEdge = []; self.prevState = []; self.settled = []; self.touched = []
        self.heap = MinHeap()
        defer {
            self.dist = dist; self.prevEdge = prevEdge; self.prevState = prevState; self.settled = settled
            self.touched = touched; self.heap = heap
        }
        for st in touched { dist[st] = .infinity; prevEdge[st] = -1; prevState[st] = -1; settled[st] = false }
        touched.removeAll(keepingCapacity: true)
        heap.removeAll()

        // The virtual start node reaches `from` at cost t * c and `to` at (1 - t) * c (door penalty
        // included proportionally: an estimate just past the door has almost paid it).
        for (v, d) in [(a, start.parameter * c0), (b, (1 - start.parameter) * c0)] where d < dist[2 * v] {
            if !dist[2 * v].isFinite { touched.append(2 * v) }
            dist[2 * v] = d; prevEdge[2 * v] = Int32(e0); prevState[2 * v] = -2
            heap.push(d, 2 * v)
        }
        var reached = -1
        let adjStart = graph.adjStart, adjNode = graph.adjNode, adjEdge = graph.adjEdge, edgeKind = graph.edgeKind
        let edgeCost = self.edgeCost, rideCost = self.rideCost, boardingPenalty = self.boardingPenalty
        adjStart.withUnsafeBufferPointer { adjStart in
        adjNode.withUnsafeBufferPointer { adjNode in
        adjEdge.withUnsafeBufferPointer { adjEdge in
        edgeCost.withUnsafeBufferPointer { edgeCost in
        rideCost.withUnsafeBufferPointer { rideCost in
        boardingPenalty.withUnsafeBufferPointer { boardingPenalty in
        edgeKind.withUnsafeBufferPointer { edgeKind in
        dist.withUnsafeMutableBufferPointer { dist in
        prevEdge.withUnsafeMutableBufferPointer { prevEdge in
        prevState.withUnsafeMutableBufferPointer { prevState in
        settled.withUnsafeMutableBufferPointer { settled in
            while let (d, st) = heap.pop() {
                if settled[st] || d > dist[st] { continue }
                settled[st] = true
                let v = st >> 1
                if v == destination { reached = st; break }
                let inRide = (st & 1) == 1
                for k in adjStart[v]..<adjStart[v + 1] {
                    let e = Int(adjEdge[k])
                    let w = Int(adjNode[k])
                    let nd: Double
                    let ns: Int
                    if edgeKind[e] == .horizontal {
                        nd = d + edgeCost[e]
                        ns = 2 * w
                    } else {
                        nd = d + rideCost[e] + (inRide ? 0 : boardingPenalty[e])  // +infinity when excluded
                        ns = 2 * w + 1
                    }
                    if settled[ns] { continue }
                    if nd < dist[ns] {
                        if !dist[ns].isFinite { touched.append(ns) }
                        dist[ns] = nd
                        prevEdge[ns] = Int32(e)
                        prevState[ns] = Int32(st)
                        heap.push(nd, ns)
                    }
                }
            }
        }}}}}}}}}}}
        guard reached >= 0 else { return nil }
        var nodesRev: [Int] = []
        var edgesRev: [Int] = []
        var st = reached
        while st >= 0 {
            nodesRev.append(st >> 1)
            edgesRev.append(Int(prevEdge[st]))  // the last one is the snapped edge, from the virtual start
            st = Int(prevState[st])
        }
        return PathResult(start: start, nodeIndices: nodesRev.reversed(), edgeIndices: edgesRev.reversed(),
                          costMeters: dist[reached])
    }
}

/// Binary min-heap of (cost, node) in one flat array; duplicates allowed (lazy deletion in Dijkstra).
/// Sifts move a hole instead of swapping pairs.
struct MinHeap {
    private struct Entry { var key: Double; var value: Int32 }
    private var items: [Entry] = []

    mutating func removeAll() { items.removeAll(keepingCapacity: true) }

    mutating func push(_ key: Double, _ value: Int) {
        let entry = Entry(key: key, value: Int32(value))
        items.append(entry)
        items.withUnsafeMutableBufferPointer { h in
            var i = h.count - 1
            while i > 0 {
                let p = (i - 1) >> 1
                if h[p].key <= key { break }
                h[i] = h[p]
                i = p
            }
            h[i] = entry
        }
    }

    mutating func pop() -> (Double, Int)? {
        guard let top = items.first else { return nil }
        let last = items.removeLast()
        if !items.isEmpty {
            items.withUnsafeMutableBufferPointer { h in
                let n = h.count
                var i = 0
                while true {
                    let l = 2 * i + 1
                    if l >= n { break }
                    var m = l
                    if l + 1 < n && h[l + 1].key < h[l].key { m = l + 1 }
                    if h[m].key >= last.key { break }
                    h[i] = h[m]
                    i = m
                }
                h[i] = last
            }
        }
        return (top.key, Int(top.value))
    }
}
