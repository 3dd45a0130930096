import Foundation
import Maps

/// The walls of one floor in a uniform grid, for the simulator's geometric queries: does a segment cross a
/// wall (truth steps, sign lines of sight), how far is a point from the nearest wall (clearance of the walker),
/// and where does a horizontal ray first hit a wall (the image renderer). Meters, map frame.
///
/// Algorithm: each wall is registered in every grid cell its bounding box overlaps (cells of `cellMeters`);
/// queries visit only the cells the query touches. Segment tests are exact (orientation predicates, with
/// touching counted as crossing).
public struct FloorGeometry: Sendable {
    /// The floor's walls.
    public let walls: [Wall]
    /// Grid cell size, meters.
    public let cellMeters: Double
    private let originX: Double, originY: Double
    private let columns: Int, rows: Int
    private let cells: [[Int32]]

    /// Builds the index for `walls` with cells of `cellMeters` (1 m suits corridors and imported masks).
    public init(walls: [Wall], cellMeters: Double = 1.0) {
        self.walls = walls
        self.cellMeters = cellMeters
        var minX = Double.infinity, minY = Double.infinity, maxX = -Double.infinity, maxY = -Double.infinity
        for w in walls {
            minX = min(minX, w.from.x, w.to.x); maxX = max(maxX, w.from.x, w.to.x)
            minY = min(minY, w.from.y, w.to.y); maxY = max(maxY, w.from.y, w.to.y)
        }
        if walls.isEmpty { minX = 0; minY = 0; maxX = 1; maxY = 1 }
        originX = minX - cellMeters; originY = minY - cellMeters
        columns = max(1, Int(((maxX - originX) / cellMeters).rounded(.up)) + 2)
        rows = max(1, Int(((maxY - originY) / cellMeters).rounded(.up)) + 2)
        var c = [[Int32]](repeating: [], count: columns * rows)
        for (i, w) in walls.enumerated() {
            let c0 = Int((min(w.from.x, w.to.x) - originX) / cellMeters), c1 = Int((max(w.from.x, w.to.x) - originX) / cellMeters)
            let r0 = Int((min(w.from.y, w.to.y) - originY) / cellMeters), r1 = Int((max(w.from.y, w.to.y) - originY) / cellMeters)
            for r in r0...r1 { for col in c0...c1 { c[r * columns + col].append(Int32(i)) } }
        }
        cells = c
    }

    private func cellRange(minX: Double, minY: Double, maxX: Double, maxY: Double) -> (Int, Int, Int, Int) {
        let c0 = max(0, Int(floor((minX - originX) / cellMeters))), c1 = min(columns - 1, Int(floor((maxX - originX) / cellMeters)))
        let r0 = max(0, Int(floor((minY - originY) / cellMeters))), r1 = min(rows - 1, Int(floor((maxY - originY) / cellMeters)))
        return (c0, c1, r0, r1)
    }

    /// Indices of the walls registered in the cells overlapping the box (each at most once).
    private func candidates(minX: Double, minY: Double, maxX: Double, maxY: Double) -> [Int] {
        let (c0, c1, r0, r1) = cellRange(minX: minX, minY: minY, maxX: maxX, maxY: maxY)
        guard c0 <= c1, r0 <= r1 else { return [] }
        if c0 == c1 && r0 == r1 { return cells[r0 * columns + c0].map(Int.init) }
        var seen = Set<Int32>()
        var out: [Int] = []
        for r in r0...r1 { for c in c0...c1 { for i in cells[r * columns + c] where seen.insert(i).inserted { out.append(Int(i)) } } }
        return out
    }

    /// True when the segment from `a` to `b` crosses or touches a wall.
    public func segmentCrossesWall(_ a: Point2, _ b: Point2) -> Bool {
        for i in candidates(minX: min(a.x, b.x), minY: min(a.y, b.y), maxX: max(a.x, b.x), maxY: max(a.y, b.y)) {
            if Geometry.segmentsIntersect(a, b, walls[i].from, walls[i].to) { return true }
        }
        return false
    }

    /// Distance from `p` to the nearest wall, meters, searched out to `maxMeters` (returns `maxMeters` when no
    /// wall is closer).
    public func clearance(at p: Point2, maxMeters: Double = 2.0) -> Double {
        var best = maxMeters
        for i in candidates(minX: p.x - maxMeters, minY: p.y - maxMeters, maxX: p.x + maxMeters, maxY: p.y + maxMeters) {
            best = min(best, Self.distance(p, walls[i].from, walls[i].to))
        }
        return best
    }

    /// Distance along the horizontal ray from `p` in direction (`dx`, `dy`) (need not be unit) to the first wall,
    /// in units of the direction vector's length, up to `maxT`; nil when nothing is hit. Walks the grid cells
    /// the ray crosses (Amanatides and Woo, "A fast voxel traversal algorithm", 1987).
    public func firstHit(from p: Point2, dx: Double, dy: Double, maxT: Double) -> (t: Double, wall: Int)? {
        var col = Int(floor((p.x - originX) / cellMeters)), row = Int(floor((p.y - originY) / cellMeters))
        let stepC = dx > 0 ? 1 : -1, stepR = dy > 0 ? 1 : -1
        let nextX = originX + Double(col + (dx > 0 ? 1 : 0)) * cellMeters
        let nextY = originY + Double(row + (dy > 0 ? 1 : 0)) * cellMeters
        var tMaxX = dx != 0 ? (nextX - p.x) / dx : .infinity
        var tMaxY = dy != 0 ? (nextY - p.y) / dy : .infinity
        let tDeltaX = dx != 0 ? cellMeters / abs(dx) : .infinity
        let tDeltaY = dy != 0 ? cellMeters / abs(dy) : .infinity
        var best: (t: Double, wall: Int)?
        var tEnter = 0.0
        while tEnter <= maxT {
            if col >= 0, col < columns, row >= 0, row < rows {
                for wi in cells[row * columns + col] {
                    let w = walls[Int(wi)]
                    if let t = Self.rayHit(p, dx, dy, w.from, w.to), t >= 0, t <= maxT, t < (best?.t ?? .infinity) {
                        best = (t, Int(wi))
                    }
                }
            } else if (col < 0 && stepC < 0) || (col >= columns && stepC > 0) || (row < 0 && stepR < 0) || (row >= rows && stepR > 0) {
                break
            }
            let tExit = min(tMaxX, tMaxY)
            if let b = best, b.t <= tExit { return b }
            tEnter = tExit
            if tMaxX < tMaxY { col += stepC; tMaxX += tDeltaX } else { row += stepR; tMaxY += tDeltaY }
        }
        return best
    }

    // MARK: - Primitives

    /// Ray parameter t at which p + t*d meets segment [a, b], nil when parallel or missed.
    static func rayHit(_ p: Point2, _ dx: Double, _ dy: Double, _ a: Point2, _ b: Point2) -> Double? {
        let ex = b.x - a.x, ey = b.y - a.y
        let denom = dx * ey - dy * ex
        if abs(denom) < 1e-15 { return nil }
        let wx = a.x - p.x, wy = a.y - p.y
        let t = (wx * ey - wy * ex) / denom
        let s = (wx * dy - wy * dx) / denom
        return (s >= 0 && s <= 1) ? t : nil
    }

    /// Distance from point p to segment [a, b], meters. `Geometry.distance(from:toSegmentFrom:to:)` with `hypot`
    /// (kept: the simulator's committed walks depend on these exact values).
    static func distance(_ p: Point2, _ a: Point2, _ b: Point2) -> Double {
        let ex = b.x - a.x, ey = b.y - a.y
        let l2 = ex * ex + ey * ey
        var t = l2 > 0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2 : 0
        t = max(0, min(1, t))
        return hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey))
    }
}
