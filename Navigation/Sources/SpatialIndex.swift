// Uniform grids over line segments, one per floor: graph edges (for snapping the location estimate) and
// walls (for checking that the snap does not go through a wall). A uniform grid suits floor plans:
// segments are short and evenly spread, so a query touches a few cells; building it is linear.
import Foundation

/// A uniform grid of cells, each listing the segments that pass through it (compressed rows).
struct SegmentGrid: Sendable {
    let segments: [(Vec2, Vec2)]
    let cellMeters: Double
    let originX: Double, originY: Double
    let nx: Int, ny: Int
    /// Segments in cell c are `items[cellStart[c] ..< cellStart[c + 1]]` (indices into `segments`).
    let cellStart: [Int]
    let items: [Int32]

    /// At most this many cells: a map with far-flung coordinates gets coarser cells instead of running out
    /// of memory.
    static let maxCells = 1 << 22

    init(segments: [(Vec2, Vec2)], cellMeters requestedCellMeters: Double) {
        self.segments = segments
        var minX = Double.infinity, minY = Double.infinity, maxX = -Double.infinity, maxY = -Double.infinity
        for (a, b) in segments {
            minX = min(minX, a.x, b.x); minY = min(minY, a.y, b.y)
            maxX = max(maxX, a.x, b.x); maxY = max(maxY, a.y, b.y)
        }
        if segments.isEmpty { minX = 0; minY = 0; maxX = 0; maxY = 0 }
        let area = (maxX - minX + requestedCellMeters) * (maxY - minY + requestedCellMeters)
        let cellMeters = max(requestedCellMeters, (area / Double(Self.maxCells)).squareRoot() * 1.01)
        self.cellMeters = cellMeters
        originX = minX; originY = minY
        nx = max(1, Int(((maxX - minX) / cellMeters).rounded(.down)) + 1)
        ny = max(1, Int(((maxY - minY) / cellMeters).rounded(.down)) + 1)
        // Two passes: count, then fill. A segment goes in every cell of its bounding box whose centre lies
        // within half a cell diagonal of it (a conservative test: no cell the segment touches is missed).
        let halfDiagonal = cellMeters * 0.5 * 2.0.squareRoot() + 1e-9
        var cellsOf: [[Int]] = []
        cellsOf.reserveCapacity(segments.count)
        var counts = [Int](repeating: 0, count: nx * ny)
        for (a, b) in segments {
            var cells: [Int] = []
            let x0 = Self.clampedCell((min(a.x, b.x) - minX) / cellMeters, nx)
            let x1 = Self.clampedCell((max(a.x, b.x) - minX) / cellMeters, nx)
            let y0 = Self.clampedCell((min(a.y, b.y) - minY) / cellMeters, ny)
            let y1 = Self.clampedCell((max(a.y, b.y) - minY) / cellMeters, ny)
            for cy in y0...y1 {
                for cx in x0...x1 {
                    let centre = Vec2(minX + (Double(cx) + 0.5) * cellMeters, minY + (Double(cy) + 0.5) * cellMeters)
                    if projectOntoSegment(centre, a, b).distance <= halfDiagonal {
                        cells.append(cy * nx + cx); counts[cy * nx + cx] += 1
                    }
                }
            }
            cellsOf.append(cells)
        }
        var start = [Int](repeating: 0, count: nx * ny + 1)
        for c in 0..<(nx * ny) { start[c + 1] = start[c] + counts[c] }
        var fill = start
        var items = [Int32](repeating: 0, count: start[nx * ny])
        for (s, cells) in cellsOf.enumerated() {
            for c in cells { items[fill[c]] = Int32(s); fill[c] += 1 }
        }
        cellStart = start
        self.items = items
    }

    @inline(__always)
    static func clampedCell(_ v: Double, _ n: Int) -> Int {
        guard v.isFinite else { return 0 }
        return max(0, min(n - 1, Int(v.rounded(.down))))
    }

    /// Calls `body` with every segment index listed in the cells overlapping the box; a segment may be
    /// reported more than once.
    @inline(__always)
    func forEachSegment(inBoxMinX x0: Double, minY y0: Double, maxX x1: Double, maxY y1: Double,
                        _ body: (Int) -> Bool) {
        guard !segments.isEmpty else { return }
        let cx0 = Self.clampedCell((x0 - originX) / cellMeters, nx), cx1 = Self.clampedCell((x1 - originX) / cellMeters, nx)
        let cy0 = Self.clampedCell((y0 - originY) / cellMeters, ny), cy1 = Self.clampedCell((y1 - originY) / cellMeters, ny)
        for cy in cy0...cy1 {
            for cx in cx0...cx1 {
                let c = cy * nx + cx
                for k in cellStart[c]..<cellStart[c + 1] where !body(Int(items[k])) { return }
            }
        }
    }

    /// True when the segment a-b properly crosses any stored segment.
    func crosses(_ a: Vec2, _ b: Vec2) -> Bool {
        var hit = false
        forEachSegment(inBoxMinX: min(a.x, b.x), minY: min(a.y, b.y), maxX: max(a.x, b.x), maxY: max(a.y, b.y)) { s in
            let (p, q) = segments[s]
            if segmentsCrossProperly(a, b, p, q) { hit = true; return false }
            return true
        }
        return hit
    }
}

/// Result of a nearest-segment query on one floor.
struct SegmentHit {
    /// Index into the floor's edge list (`FloorSpatialIndex.edgeIds` maps it to a graph edge).
    var segment: Int
    /// Parameter along the segment, 0 at its first end.
    var t: Double
    var point: Vec2
    var distance: Double
    /// True when no unobstructed segment was found within the search radius and the nearest one was used.
    var obstructed: Bool
}

/// The spatial index of one floor: its horizontal graph edges and its walls.
struct FloorSpatialIndex: Sendable {
    let edgesGrid: SegmentGrid
    /// Graph edge index of each segment of `edgesGrid`.
    let edgeIds: [Int]
    let walls: SegmentGrid

    init(edgeSegments: [(Vec2, Vec2)], edgeIds: [Int], walls: [(Vec2, Vec2)], cellMeters: Double) {
        edgesGrid = SegmentGrid(segments: edgeSegments, cellMeters: cellMeters)
        self.edgeIds = edgeIds
        self.walls = SegmentGrid(segments: walls, cellMeters: cellMeters)
    }

    /// The nearest point on an edge such that the straight line from `p` to it crosses no wall; searched in
    /// square rings of cells around `p` until the ring cannot hold anything nearer. When nothing
    /// unobstructed lies within `maxClearSearchMeters`, returns the nearest edge regardless of walls, flagged
    /// `obstructed`. Nil only when the floor has no edges.
    func nearestEdge(to p: Vec2, maxClearSearchMeters: Double) -> SegmentHit? {
        let g = edgesGrid
        guard !g.segments.isEmpty else { return nil }
        let fx = (p.x - g.originX) / g.cellMeters, fy = (p.y - g.originY) / g.cellMeters
        let cx = SegmentGrid.clampedCell(fx, g.nx), cy = SegmentGrid.clampedCell(fy, g.ny)
        var bestAny: SegmentHit? = nil
        var bestClear: SegmentHit? = nil
        var obstructedSeen: [Int] = []
        let maxRing = max(g.nx, g.ny)
        var r = 0
        while r <= maxRing {
            // Lower bound on the distance from p to any cell of ring r: p's distance to the outside of the
            // square of rings 0..r-1 (0 when p lies outside that square, e.g. beyond the grid).
            if r > 0 {
                let bx0 = g.originX + Double(cx - r + 1) * g.cellMeters, bx1 = g.originX + Double(cx + r) * g.cellMeters
                let by0 = g.originY + Double(cy - r + 1) * g.cellMeters, by1 = g.originY + Double(cy + r) * g.cellMeters
                var lb = 0.0
                if p.x >= bx0 && p.x <= bx1 && p.y >= by0 && p.y <= by1 {
                    lb = min(p.x - bx0, bx1 - p.x, p.y - by0, by1 - p.y)
                }
                if let c = bestClear, lb >= c.distance { break }
                if bestClear == nil, let a = bestAny, lb > maxClearSearchMeters, lb >= a.distance { break }
            }
            let y0 = cy - r, y1 = cy + r, x0 = cx - r, x1 = cx + r
            for y in y0...y1 where y >= 0 && y < g.ny {
                let fullRow = (y == y0 || y == y1)
                var x = x0
                while x <= x1 {
                    if x >= 0 && x < g.nx {
                        let c = y * g.nx + x
                        for k in g.cellStart[c]..<g.cellStart[c + 1] {
                            let s = Int(g.items[k])
                            let (a, b) = g.segments[s]
                            let pr = projectOntoSegment(p, a, b)
                            if bestAny == nil || pr.distance < bestAny!.distance {
                                bestAny = SegmentHit(segment: s, t: pr.t, point: pr.point, distance: pr.distance, obstructed: false)
                            }
                            if pr.distance < (bestClear?.distance ?? .infinity) && pr.distance <= maxClearSearchMeters
                                && !obstructedSeen.contains(s) {
                                if walls.crosses(p, pr.point) {
                                    obstructedSeen.append(s)
                                } else {
                                    bestClear = SegmentHit(segment: s, t: pr.t, point: pr.point, distance: pr.distance, obstructed: false)
                                }
                            }
                        }
                    }
                    // Interior rows of the ring only have their two end cells.
                    x = (fullRow || x == x1) ? x + 1 : x1
                }
            }
            r += 1
        }
        if let c = bestClear { return c }
        guard var a = bestAny else { return nil }
        a.obstructed = walls.crosses(p, a.point)
        return a
    }
}
