import Foundation
import Maps
import SessionFormat

/// Renders the simulated camera's images so that the whole detection path (unrolling, detector, slice
/// measurement, range formula) can run on simulated walks.
///
/// A small pure-Swift ray caster: for each pixel, the ray `CameraPose.rayInWorld(u:v:)` of the true camera pose
/// (the map as world: x east, y up, z = -north) is intersected with
/// - the floor's walls extruded from 0 to `wallHeightMeters` (found through `FloorGeometry.firstHit`, a grid walk
///   over the ray's horizontal projection),
/// - the floor (z = 0, a 0.5 m tile pattern) and the ceiling (z = `wallHeightMeters`, light panels),
/// - the signs: vertical quads `widthMeters` x `heightMeters` with their bottom edge at `mountingHeightMeters`
///   (2.3 m when unsurveyed), 1 cm in front of their wall, visible from the side their `facing` points to (both
///   sides when double-sided), textured with a red "EXIT" (5 x 7 pixel glyphs) on a white plate with a red rim.
/// Shading: a headlight term (cosine between the ray and the surface normal) with distance falloff; signs are
/// self-lit. Pixels whose footprint touches a sign are supersampled 3 x 3, so small distant signs keep their
/// shape. Each image gets seeded Gaussian pixel noise (sigma 2 grey levels). Images are in sensor orientation,
/// as ARKit captures them: held in portrait, the world appears rotated by 90 degrees.
struct SceneRenderer: Sendable {
    /// Intrinsics of rendered images: the iPhone 8 camera (fx = 1602 at 1920 x 1440) scaled to 640 x 480.
    static let imageIntrinsics = CameraIntrinsics(fx: 534, fy: 534, cx: 320, cy: 240, width: 640, height: 480)
    /// Height of walls and ceiling, meters.
    static let wallHeightMeters = 3.0
    let floors: [String: Floor]
    let geometry: [String: FloorGeometry]
    let states: [TrueCameraState]
    let intrinsics: CameraIntrinsics
    /// Seed of the pixel noise.
    var seed: UInt64 = 0

    /// A sign prepared for ray tests.
    struct SignQuad {
        var center: Point2     // face centre on the plan, 1 cm in front of the wall
        var normal: Point2     // unit facing
        var along: Point2      // unit, to the reader's right
        var halfWidth: Double
        var bottom: Double
        var top: Double
        var doubleSided: Bool
    }

    /// Binary PPM (P6) of frame `frameIndex`.
    func renderPPM(frameIndex: Int) -> Data {
        let rgb = render(frameIndex: frameIndex)
        var data = Data("P6\n\(intrinsics.width) \(intrinsics.height)\n255\n".utf8)
        data.append(contentsOf: rgb)
        return data
    }

    /// Row-major RGB bytes of frame `frameIndex`.
    func render(frameIndex: Int) -> [UInt8] {
        let s = states[frameIndex]
        let k = intrinsics
        let pose = SignObservationModel.mapPose(s)
        let geo = geometry[s.floorId] ?? FloorGeometry(walls: [])
        let camH = s.heightAboveFloorMeters
        let cam = s.position.asPoint
        // Only Exit signs are drawn: the detectors know no other class yet (placards and pictograms are
        // sighted through the simulator's recorded observations only).
        let exitSigns = (floors[s.floorId]?.signs ?? []).filter { $0.kind == SignKindSpec.defaultExit.kind }
        let quads: [SignQuad] = exitSigns.compactMap { sign in
            let n = hypot(sign.facing.x, sign.facing.y)
            guard n > 0 else { return nil }
            let nx = sign.facing.x / n, ny = sign.facing.y / n
            let c = Point2(sign.position.x + 0.01 * nx, sign.position.y + 0.01 * ny)
            if hypot(c.x - cam.x, c.y - cam.y) > 25 { return nil }
            let bottom = sign.mountingHeightMeters ?? SignObservationModel.defaultMountingHeightMeters
            return SignQuad(center: c, normal: Point2(nx, ny), along: Point2(-ny, nx), halfWidth: sign.widthMeters / 2,
                            bottom: bottom, top: bottom + sign.heightMeters, doubleSided: sign.doubleSided)
        }
        var rng = SeededRandom(seed: seed ^ UInt64(frameIndex) &* 0x9E37_79B9, stream: 99)
        var out = [UInt8](repeating: 0, count: k.width * k.height * 3)
        let ctx = Context(pose: pose, intrinsics: k, geo: geo, cam: cam, camH: camH, quads: quads)
        for v in 0..<k.height {
            for u in 0..<k.width {
                var color = ctx.shade(u: Double(u) + 0.5, v: Double(v) + 0.5)
                if !quads.isEmpty && ctx.footprintTouchesSign(u: Double(u), v: Double(v)) {
                    var acc = (0.0, 0.0, 0.0)
                    for i in 0..<3 { for j in 0..<3 {
                        let c = ctx.shade(u: Double(u) + (Double(i) + 0.5) / 3, v: Double(v) + (Double(j) + 0.5) / 3)
                        acc.0 += c.0; acc.1 += c.1; acc.2 += c.2
                    } }
                    color = (acc.0 / 9, acc.1 / 9, acc.2 / 9)
                }
                let noise = 2.0 * rng.normal()
                let o = (v * k.width + u) * 3
                out[o] = Self.byte(color.0 * 255 + noise)
                out[o + 1] = Self.byte(color.1 * 255 + noise)
                out[o + 2] = Self.byte(color.2 * 255 + noise)
            }
        }
        return out
    }

    private static func byte(_ x: Double) -> UInt8 { UInt8(max(0, min(255, x.rounded()))) }

    /// Per-image constants and the per-ray shading.
    struct Context {
        let pose: CameraPose
        let intrinsics: CameraIntrinsics
        let geo: FloorGeometry
        let cam: Point2
        let camH: Double
        let quads: [SignQuad]

        /// Map-frame ray (east, north, up) through pixel (u, v).
        func ray(u: Double, v: Double) -> (Double, Double, Double) {
            let r = pose.rayInWorld(u: u, v: v, intrinsics: intrinsics)
            return (r.x, -r.z, r.y)
        }

        /// Ray parameter and texture colour of the nearest sign hit, if any.
        func signHit(_ d: (Double, Double, Double), maxT: Double) -> (t: Double, color: (Double, Double, Double))? {
            var best: (Double, (Double, Double, Double))?
            for q in quads {
                let dn = d.0 * q.normal.x + d.1 * q.normal.y
                if abs(dn) < 1e-12 { continue }
                if dn > 0 && !q.doubleSided { continue }
                let t = ((q.center.x - cam.x) * q.normal.x + (q.center.y - cam.y) * q.normal.y) / dn
                guard t > 0, t < maxT, t < (best?.0 ?? .infinity) else { continue }
                let px = cam.x + t * d.0, py = cam.y + t * d.1, pz = camH + t * d.2
                let a = (px - q.center.x) * q.along.x + (py - q.center.y) * q.along.y
                guard abs(a) <= q.halfWidth, pz >= q.bottom, pz <= q.top else { continue }
                var s = (a + q.halfWidth) / (2 * q.halfWidth)
                if dn > 0 { s = 1 - s }   // the back face reads mirrored otherwise
                let tt = (q.top - pz) / (q.top - q.bottom)  // 0 at the top
                best = (t, SceneRenderer.exitTexture(s: s, t: tt))
            }
            return best.map { (t: $0.0, color: $0.1) }
        }

        /// Colour seen along the ray through (u, v).
        func shade(u: Double, v: Double) -> (Double, Double, Double) {
            let d = ray(u: u, v: v)
            let horiz = hypot(d.0, d.1)
            let len = (horiz * horiz + d.2 * d.2).squareRoot()
            // Nearest of wall, floor, ceiling.
            var tSurface = Double.infinity
            var surface = 0  // 0 none, 1 wall, 2 floor, 3 ceiling
            var wallIndex = -1
            if horiz > 1e-9, let hit = geo.firstHit(from: cam, dx: d.0, dy: d.1, maxT: 60 / horiz) {
                let z = camH + hit.t * d.2
                if z >= 0 && z <= SceneRenderer.wallHeightMeters { tSurface = hit.t; surface = 1; wallIndex = hit.wall }
            }
            if d.2 < -1e-9 { let t = -camH / d.2; if t < tSurface { tSurface = t; surface = 2 } }
            if d.2 > 1e-9 { let t = (SceneRenderer.wallHeightMeters - camH) / d.2; if t < tSurface { tSurface = t; surface = 3 } }
            if let s = signHit(d, maxT: tSurface + 1e-6) { return s.color }
            let dist = tSurface * len
            let fall = 1 / (1 + 0.04 * dist)
            switch surface {
            case 1:
                let w = geo.walls[wallIndex]
                let ex = w.to.x - w.from.x, ey = w.to.y - w.from.y
                let el = max(1e-12, hypot(ex, ey))
                let cosine = abs((d.0 * -ey + d.1 * ex) / (el * len))
                let z = camH + tSurface * d.2
                // A darker skirting board at the bottom.
                let base = z < 0.1 ? 0.45 : 0.78
                let g = base * (0.35 + 0.65 * cosine) * fall
                return (g * 0.98, g * 0.96, g * 0.9)
            case 2:
                let px = cam.x + tSurface * d.0, py = cam.y + tSurface * d.1
                let tile = (Int(floor(px / 0.5)) + Int(floor(py / 0.5))) & 1 == 0 ? 0.42 : 0.36
                let cosine = abs(d.2) / len
                let g = tile * (0.5 + 0.5 * cosine) * fall
                return (g, g * 0.95, g * 0.88)
            case 3:
                let px = cam.x + tSurface * d.0, py = cam.y + tSurface * d.1
                let fx = px - 2.4 * floor(px / 2.4), fy = py - 2.4 * floor(py / 2.4)
                let panel = fx > 0.6 && fx < 1.2 && fy > 0.6 && fy < 1.8
                let g = (panel ? 0.97 : 0.7) * (panel ? 1 : fall)
                return (g, g, g)
            default:
                return (0.1, 0.1, 0.1)
            }
        }

        /// True when any corner of the pixel's footprint sees a sign (then the pixel is supersampled).
        func footprintTouchesSign(u: Double, v: Double) -> Bool {
            for (du, dv) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)] {
                if signHit(ray(u: u + du, v: v + dv), maxT: .infinity) != nil { return true }
            }
            return false
        }
    }

    /// 5 x 7 glyphs of E, X, I, T (rows top to bottom, '#' = ink).
    static let glyphs: [[String]] = [
        ["#####", "#....", "#....", "####.", "#....", "#....", "#####"],
        ["#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"],
        [".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."],
        ["#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."],
    ]

    /// Colour of the sign face at texture coordinates (s right, t down) in [0, 1]: red "EXIT" on white, red rim.
    static func exitTexture(s: Double, t: Double) -> (Double, Double, Double) {
        let red = (0.85, 0.08, 0.06), white = (0.97, 0.97, 0.95)
        if s < 0.04 || s > 0.96 || t < 0.06 || t > 0.94 { return red }
        // Text block: 23 x 7 cells in the middle 80 % x 56 %.
        let x = (s - 0.1) / 0.8, y = (t - 0.22) / 0.56
        guard x >= 0, x < 1, y >= 0, y < 1 else { return white }
        let col = Int(x * 23), row = Int(y * 7)
        let letter = col / 6, inLetter = col % 6
        guard letter < 4, inLetter < 5 else { return white }
        let line = Array(glyphs[letter][row])
        return line[inLetter] == "#" ? red : white
    }
}
