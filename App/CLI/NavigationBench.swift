// `wayfinder bench` entries for navigation: snapping and routing on a generated 5,000-node building,
// each with a baseline measured in the same run (linear-scan snapping, array-based O(V^2) Dijkstra).
import Dispatch
import Foundation
import Maps
import Navigation

/// Navigation benchmarks, called by `wayfinder bench`.
enum NavigationBench {
    /// Runs the navigation benchmarks; returns one row per measurement: name, nanoseconds per operation,
    /// and the same operation's baseline in nanoseconds (nil when there is none).
    /// - Parameter iterations: queries per measurement (the O(V^2) baseline runs min(iterations, 20)).
    static func run(iterations: Int) -> [(name: String, nanosecondsPerOp: Double, baselineNanosecondsPerOp: Double?)] {
        let n = max(1, iterations)
        let building = generatedBuilding(columns: 100, rows: 50, spacingMeters: 3, seed: 2026)
        guard let graph = try? RoutingGraph(building: building) else { return [] }
        let router = Router(graph: graph)
        let baseline = Baseline(graph: graph, router: router, building: building)

        var rng = SplitMix(state: 99)
        let width = 99 * 3.0, height = 49 * 3.0
        let queries: [(Point2, Int)] = (0..<n).map { _ in
            (Point2(x: rng.unit() * width, y: rng.unit() * height), Int(rng.next() % UInt64(graph.nodeCount)))
        }

        // Warm-up (first-touch allocation of the router's scratch arrays).
        if let s = router.snap(queries[0].0, floorId: "1") { _ = router.shortestPath(from: s, to: queries[0].1) }

        var sink = 0.0
        let snapNs = timePerOp(n) { i in sink += router.snap(queries[i].0, floorId: "1")?.distanceMeters ?? 0 }
        let snaps = queries.map { router.snap($0.0, floorId: "1")! }
        let routeNs = timePerOp(n) { i in sink += router.shortestPath(from: snaps[i], to: queries[i].1)?.costMeters ?? 0 }
        let bothNs = timePerOp(n) { i in
            if let s = router.snap(queries[i].0, floorId: "1") {
                sink += router.shortestPath(from: s, to: queries[i].1)?.costMeters ?? 0
            }
        }
        let nb = min(n, 20)
        let baseSnapNs = timePerOp(nb) { i in sink += baseline.snap(queries[i].0).distance }
        let baseRouteNs = timePerOp(nb) { i in sink += baseline.route(from: snaps[i], to: queries[i].1) }
        let baseBothNs = timePerOp(nb) { i in
            let s = baseline.snap(queries[i].0)
            sink += baseline.route(from: SnappedPosition(edgeIndex: s.edge, parameter: s.t, point: s.point, floorId: "1",
                                                         distanceMeters: s.distance, throughWall: false),
                                   to: queries[i].1)
        }

        // Steady-state navigator update while walking a long route (no re-route): the per-update cost.
        var updateNs = Double.nan
        if let nav = try? Navigator(building: building, destinationId: "n\(graph.nodeCount - 1)") {
            let start = graph.position(ofNode: 0)
            _ = nav.update(NavigationInput(t: 0, positionInMap: start, floorId: "1", headingRad: 0, isLocalized: true))
            if let route = nav.currentRoute {
                var walk: [NavigationInput] = []
                var t = 0.1
                for k in 1..<route.points.count where route.points[k].floorId == "1" {
                    let a = route.points[k - 1].position, b = route.points[k].position
                    let len = ((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y)).squareRoot()
                    let steps = max(1, Int(len / 0.12))
                    for j in 1...steps {
                        let f = Double(j) / Double(steps)
                        walk.append(NavigationInput(t: t, positionInMap: Point2(x: a.x + (b.x - a.x) * f, y: a.y + (b.y - a.y) * f),
                                                    floorId: "1", headingRad: atan2(b.y - a.y, b.x - a.x), isLocalized: true))
                        t += 0.1
                    }
                }
                let m = min(walk.count, max(n, 1000))
                updateNs = timePerOp(m) { i in sink += Double(nav.update(walk[i]).count) }
            }
        }
        if sink == 42.4242 { print("") }  // keeps the work observable to the optimiser

        let v = graph.nodeCount
        return [
            (name: "navigation.snap (edge grid + wall grid, \(v) nodes)", nanosecondsPerOp: snapNs,
             baselineNanosecondsPerOp: baseSnapNs),
            (name: "navigation.route (binary-heap Dijkstra, \(v) nodes)", nanosecondsPerOp: routeNs,
             baselineNanosecondsPerOp: baseRouteNs),
            (name: "navigation.snap+route (\(v) nodes; baseline linear snap + O(V^2) Dijkstra)", nanosecondsPerOp: bothNs,
             baselineNanosecondsPerOp: baseBothNs),
            (name: "navigation.update (steady state along a route, \(v) nodes)", nanosecondsPerOp: updateNs,
             baselineNanosecondsPerOp: nil),
        ]
    }

    /// Mean CPU time of `body` on this thread, nanoseconds: thread CPU time rather than wall time, so
    /// that other processes sharing the machine do not inflate the figure ("on one core").
    private static func timePerOp(_ count: Int, _ body: (Int) -> Void) -> Double {
        let t0 = threadCPUNanoseconds()
        for i in 0..<count { body(i) }
        let t1 = threadCPUNanoseconds()
        return Double(t1 - t0) / Double(max(1, count))
    }

    private static func threadCPUNanoseconds() -> UInt64 {
        var ts = timespec()
        guard clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0 else { return DispatchTime.now().uptimeNanoseconds }
        return UInt64(ts.tv_sec) * 1_000_000_000 + UInt64(ts.tv_nsec)
    }

    /// SplitMix64: a fixed-seed generator so every run measures the same queries.
    private struct SplitMix {
        var state: UInt64
        mutating func next() -> UInt64 {
            state &+= 0x9E37_79B9_7F4A_7C15
            var z = state
            z = (z ^ (z >> 30)) &* 0xBF58_476D_1CE4_E5B9
            z = (z ^ (z >> 27)) &* 0x94D0_49BB_1331_11EB
            return z ^ (z >> 31)
        }
        mutating func unit() -> Double { Double(next() >> 11) / Double(1 << 53) }
    }

    /// A one-floor building: a `columns` x `rows` lattice of corridor nodes `spacingMeters` apart, 85% of the
    /// lattice edges kept (spanning-tree edges along the first row and every column always kept, so the
    /// graph is connected), and a 1 m square pillar of walls inside every block.
    static func generatedBuilding(columns: Int, rows: Int, spacingMeters s: Double, seed: UInt64) -> Building {
        var rng = SplitMix(state: seed)
        var nodes: [GraphNode] = []
        nodes.reserveCapacity(columns * rows)
        for j in 0..<rows {
            for i in 0..<columns {
                nodes.append(GraphNode(id: "n\(j * columns + i)", kind: .control, floorId: "1",
                                       position: Point2(x: Double(i) * s, y: Double(j) * s)))
            }
        }
        var edges: [GraphEdge] = []
        for j in 0..<rows {
            for i in 0..<columns {
                let v = j * columns + i
                if i + 1 < columns && (j == 0 || rng.unit() < 0.85) { edges.append(GraphEdge(from: "n\(v)", to: "n\(v + 1)")) }
                if j + 1 < rows { edges.append(GraphEdge(from: "n\(v)", to: "n\(v + columns)")) }
            }
        }
        var walls: [Wall] = []
        for j in 0..<(rows - 1) {
            for i in 0..<(columns - 1) {
                let cx = (Double(i) + 0.5) * s, cy = (Double(j) + 0.5) * s, h = 0.5
                let c = [Point2(x: cx - h, y: cy - h), Point2(x: cx + h, y: cy - h), Point2(x: cx + h, y: cy + h), Point2(x: cx - h, y: cy + h)]
                for k in 0..<4 { walls.append(Wall(from: c[k], to: c[(k + 1) % 4])) }
            }
        }
        return Building(id: "bench-lattice", name: "Benchmark lattice",
                        floors: [Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: walls)],
                        graph: NavigationGraph(nodes: nodes, edges: edges))
    }

    /// The straightforward implementations the optimised ones are compared with.
    private struct Baseline {
        let positions: [Point2]
        let from: [Int], to: [Int]
        let cost: [Double]
        let adjacency: [[(node: Int, edge: Int)]]
        let walls: [Wall]

        init(graph: RoutingGraph, router: Router, building: Building) {
            positions = (0..<graph.nodeCount).map { graph.position(ofNode: $0) }
            from = graph.edges.map { graph.nodeIndexById[$0.from]! }
            to = graph.edges.map { graph.nodeIndexById[$0.to]! }
            cost = (0..<graph.edgeCount).map { router.cost(ofEdge: $0) }
            var adj = [[(node: Int, edge: Int)]](repeating: [], count: graph.nodeCount)
            for e in 0..<graph.edgeCount { adj[from[e]].append((to[e], e)); adj[to[e]].append((from[e], e)) }
            adjacency = adj
            walls = building.floors[0].walls
        }

        private static func project(_ p: Point2, _ a: Point2, _ b: Point2) -> (t: Double, point: Point2, distance: Double) {
            let dx = b.x - a.x, dy = b.y - a.y
            let l2 = dx * dx + dy * dy
            let t = l2 > 0 ? max(0, min(1, ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2)) : 0
            let q = Point2(x: a.x + dx * t, y: a.y + dy * t)
            return (t, q, ((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y)).squareRoot())
        }

        private func blocked(_ p: Point2, _ q: Point2) -> Bool {
            func orient(_ a: Point2, _ b: Point2, _ c: Point2) -> Double { (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) }
            for w in walls {
                let d1 = orient(w.from, w.to, p), d2 = orient(w.from, w.to, q)
                let d3 = orient(p, q, w.from), d4 = orient(p, q, w.to)
                if d1 * d2 < 0 && d3 * d4 <= 0 { return true }
            }
            return false
        }

        /// Every edge's distance (linear scan), then the nearest edges in turn, each checked against every
        /// wall, until one is unobstructed (at most 20 tries, then the nearest).
        func snap(_ p: Point2) -> (edge: Int, t: Double, point: Point2, distance: Double) {
            var all = (0..<from.count).map { Self.project(p, positions[from[$0]], positions[to[$0]]) }
            var first: Int? = nil
            for _ in 0..<20 {
                var best = -1
                for e in all.indices where all[e].distance.isFinite && (best < 0 || all[e].distance < all[best].distance) { best = e }
                guard best >= 0 else { break }
                if first == nil { first = best }
                if !blocked(p, all[best].point) { return (best, all[best].t, all[best].point, all[best].distance) }
                all[best].distance = .infinity
            }
            let e = first ?? 0
            let pr = Self.project(p, positions[from[e]], positions[to[e]])
            return (e, pr.t, pr.point, pr.distance)
        }

        /// Dijkstra with a linear search for the closest unsettled node: O(V^2).
        func route(from s: SnappedPosition, to destination: Int) -> Double {
            let v = positions.count
            var dist = [Double](repeating: .infinity, count: v)
            var done = [Bool](repeating: false, count: v)
            let c = cost[s.edgeIndex]
            dist[from[s.edgeIndex]] = s.parameter * c
            dist[to[s.edgeIndex]] = min(dist[to[s.edgeIndex]], (1 - s.parameter) * c)
            for _ in 0..<v {
                var u = -1
                var best = Double.infinity
                for i in 0..<v where !done[i] && dist[i] < best { best = dist[i]; u = i }
                if u < 0 || u == destination { break }
                done[u] = true
                for (w, e) in adjacency[u] where dist[u] + cost[e] < dist[w] { dist[w] = dist[u] + cost[e] }
            }
            return dist[destination]
        }
    }
}
