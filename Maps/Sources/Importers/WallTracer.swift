/// Turns a raster wall mask into wall segments along the boundary between wall and free pixels.
///
/// Algorithm: every pixel side separating a wall pixel from a free pixel (or from outside the image) is a
/// unit boundary edge on the pixel lattice; horizontal edges on the same lattice row and vertical edges on
/// the same lattice column are merged while contiguous, giving maximal axis-aligned segments. A wall drawn
/// k pixels thick thus yields its two faces (plus end caps), as in the real building. Optionally, connected
/// wall components smaller than `minimumComponentPixels` (scanning specks) are dropped first.
/// Coordinates are lattice coordinates: x = column boundary (0...width), y = row boundary (0...height),
/// y pointing DOWN the image.
public enum WallTracer {
    /// One merged boundary segment in lattice coordinates (pixels, y down).
    public struct LatticeSegment: Hashable, Sendable {
        /// Start (x = column boundary, y = row boundary).
        public let from: Point2
        /// End.
        public let to: Point2
    }

    /// Traces the wall mask (`mask[row * width + column]`, true = wall, row 0 = top).
    public static func trace(mask: [Bool], width: Int, height: Int, minimumComponentPixels: Int = 1) -> [LatticeSegment] {
        precondition(mask.count == width * height, "mask size does not match width x height")
        let m = minimumComponentPixels > 1 ? removeSmallComponents(mask, width: width, height: height, minimum: minimumComponentPixels) : mask
        func wall(_ c: Int, _ r: Int) -> Bool { c >= 0 && r >= 0 && c < width && r < height && m[r * width + c] }
        var out: [LatticeSegment] = []
        // Horizontal edges on lattice row r (between pixel rows r-1 and r).
        for r in 0...height {
            var runStart: Int?
            for c in 0...width {
                let isEdge = c < width && wall(c, r - 1) != wall(c, r)
                if isEdge, runStart == nil { runStart = c }
                if !isEdge, let s = runStart {
                    out.append(LatticeSegment(from: Point2(Double(s), Double(r)), to: Point2(Double(c), Double(r))))
                    runStart = nil
                }
            }
        }
        // Vertical edges on lattice column c (between pixel columns c-1 and c).
        for c in 0...width {
            var runStart: Int?
            for r in 0...height {
                let isEdge = r < height && wall(c - 1, r) != wall(c, r)
                if isEdge, runStart == nil { runStart = r }
                if !isEdge, let s = runStart {
                    out.append(LatticeSegment(from: Point2(Double(c), Double(s)), to: Point2(Double(c), Double(r))))
                    runStart = nil
                }
            }
        }
        return out
    }

    /// The mask without 4-connected wall components of fewer than `minimum` pixels.
    public static func removeSmallComponents(_ mask: [Bool], width: Int, height: Int, minimum: Int) -> [Bool] {
        var out = mask
        var label = [Int32](repeating: -1, count: mask.count)
        var stack: [Int] = []
        var component: [Int] = []
        for start in 0..<mask.count where mask[start] && label[start] < 0 {
            component.removeAll(keepingCapacity: true)
            stack.append(start)
            label[start] = 0
            while let i = stack.popLast() {
                component.append(i)
                let c = i % width, r = i / width
                for (nc, nr) in [(c - 1, r), (c + 1, r), (c, r - 1), (c, r + 1)] where nc >= 0 && nr >= 0 && nc < width && nr < height {
                    let j = nr * width + nc
                    if mask[j] && label[j] < 0 { label[j] = 0; stack.append(j) }
                }
            }
            if component.count < minimum { for i in component { out[i] = false } }
        }
        return out
    }
}
