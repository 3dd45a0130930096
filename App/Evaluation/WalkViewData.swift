import Foundation
import Maps
import SessionFormat
import WayfinderCore

/// How a floor's map coordinates become SVG pixels in the trainer's page: `px = (x + offsetX) * scale`,
/// `py = (offsetY - y) * scale` (y up in the map, down on screen). One value per drawn floor, shared by the
/// static plan (Swift) and the moving layer (the page's script reads it from the data).
struct FloorFrame: Encodable {
    /// Meters added to x before scaling (margin minus the smallest wall x).
    var ox: Double
    /// Meters from which y is subtracted before scaling (largest wall y plus the margin).
    var oy: Double
    /// Pixels per meter.
    var s: Double
    /// Width and height of the floor's SVG, pixels.
    var w: Double, h: Double

    /// The frame fitting `floor`'s walls (1 m margin) into at most 1300 x 760 pixels.
    init(floor: Floor) {
        var minX = Double.infinity, minY = Double.infinity, maxX = -Double.infinity, maxY = -Double.infinity
        for w in floor.walls {
            for p in [w.from, w.to] { minX = min(minX, p.x); maxX = max(maxX, p.x); minY = min(minY, p.y); maxY = max(maxY, p.y) }
        }
        if !minX.isFinite { minX = 0; minY = 0; maxX = 10; maxY = 10 }
        let margin = 1.0
        let widthM = maxX - minX + 2 * margin, heightM = maxY - minY + 2 * margin
        s = min(1300 / widthM, 760 / heightM)
        ox = margin - minX
        oy = maxY + margin
        w = widthM * s
        h = heightM * s
    }

    /// SVG x of map x (meters), one decimal.
    func X(_ x: Double) -> String { String(format: "%.1f", (x + ox) * s) }
    /// SVG y of map y (meters), one decimal.
    func Y(_ y: Double) -> String { String(format: "%.1f", (oy - y) * s) }
}

/// Everything the trainer's page moves with its playhead, as one JSON document placed in
/// `<script type="application/json">` and read with `JSON.parse` (never executed). Compact integer units:
/// times in milliseconds, positions in centimeters (map frame), headings in milliradians, confidence and
/// weights in thousandths; floors by their index in `floors` (-1 = a floor that is not drawn). Text (what was
/// said, sign ids) stays text: the page only ever puts it into `textContent`.
struct WalkViewData: Encodable {
    /// One column per field, one entry per kept frame (one every `frameStepSeconds`, and each change of state).
    struct Frames: Encodable {
        var t: [Int] = [], x: [Int] = [], y: [Int] = [], f: [Int] = [], h: [Int] = []
        /// Confidence, thousandths.
        var c: [Int] = []
        /// 1 while localized.
        var loc: [Int] = []
        /// Number of hypotheses.
        var nh: [Int] = []
        /// Tracking: 0 normal, 1 limited, 2 lost.
        var trk: [Int] = []
        /// True position (cm) and floor index at the frame's time; empty without truth.
        var tx: [Int] = [], ty: [Int] = [], tf: [Int] = [], th: [Int] = []
        /// Horizontal error of the estimate against truth, cm; -1 on another floor; empty without truth.
        var err: [Int] = []
    }
    /// A particle cloud and the hypotheses at one moment.
    struct Cloud: Encodable {
        var t: Int
        /// Particles, flattened: floor index, x, y per particle.
        var p: [Int]
        /// Hypotheses, flattened: floor index, x, y, heading (mrad), weight (thousandths), spread (cm).
        var hyp: [Int]
    }
    /// Something said, felt or decided at a moment.
    struct Event: Encodable {
        var t: Int
        /// "said" (guidance), "prompt" (tracking prompt), "haptic", "wrong" (wrong way / off route haptic),
        /// "reroute".
        var k: String
        var text: String
    }
    /// A sign sighting: the ray from the estimated camera, and the sign it matched.
    struct Sighting: Encodable {
        var t: Int
        var f: Int
        var x0: Int, y0: Int, x1: Int, y1: Int
        var kind: String
        /// Id of the map sign nearest to where the sighting puts the sign from the estimated pose (same kind,
        /// facing the camera, within `WalkViewData.matchRadiusMeters`); "" when none.
        var match: String
        /// Its position, cm (0 when no match), and how far from the ray's end, cm.
        var sx: Int, sy: Int, md: Int
        /// The sign matched the same way from the true pose ("" without truth or without a match): when it
        /// differs from `match`, the estimate explained the sighting with the wrong sign.
        var truth: String
    }
    /// A route in force from time `t`.
    struct RouteView: Encodable {
        var t: Int
        var reroute: Bool
        /// Flattened floor index, x, y per point.
        var p: [Int]
    }
    /// A spell of degraded tracking.
    struct Spell: Encodable {
        var t0: Int, t1: Int
        /// "limited" or "lost".
        var state: String
        /// The tracking text of its first frame ("limited (excessiveMotion)").
        var text: String
    }

    var t0: Int, t1: Int
    /// Playhead position when the page opens (no #t= fragment), ms.
    var initial: Int
    /// Timeline geometry: SVG width and left label column, pixels.
    var timelineWidth: Double, timelineLeft: Double
    var floors: [FloorFrame]
    var frames: Frames
    var clouds: [Cloud]
    var events: [Event]
    var sightings: [Sighting]
    var routes: [RouteView]
    var spells: [Spell]

    /// Frames kept for the page: at most one per this many seconds (the walk's state changes little faster).
    static let frameStepSeconds = 0.1
    /// Most sightings kept (evenly subsampled beyond).
    static let maximumSightings = 1500
    /// A sighting matches a map sign of its kind at most this far from where it puts the sign, meters.
    static let matchRadiusMeters = 2.5

    /// Builds the data of a replay on `building`, drawing `floors` (in that order, by index).
    init(building: Building, floors: [Floor], result: ReplayResult, track: TruthTrack,
         timelineWidth: Double, timelineLeft: Double) {
        let floorIndex = Dictionary(floors.enumerated().map { ($1.id, $0) }, uniquingKeysWith: { a, _ in a })
        func fi(_ id: String) -> Int { floorIndex[id] ?? -1 }
        func cm(_ v: Double) -> Int { v.isFinite ? Int((v * 100).rounded()) : 0 }
        func ms(_ t: Double) -> Int { t.isFinite ? Int((t * 1000).rounded()) : 0 }
        let t0 = result.trace.first?.t ?? 0, t1 = result.trace.last?.t ?? 0
        self.t0 = ms(t0); self.t1 = ms(t1)
        self.timelineWidth = timelineWidth; self.timelineLeft = timelineLeft
        self.floors = floors.map(FloorFrame.init(floor:))

        var fr = Frames()
        var lastKept: TraceRecord?
        for (k, r) in result.trace.enumerated() {
            // Every frame step, the last frame, and each frame where the localized flag, the tracking or the floor
            // changes (so the page shows a change at the moment it happened).
            if let last = lastKept, r.t - last.t < Self.frameStepSeconds - 1e-9, k != result.trace.count - 1,
               last.localized == r.localized, last.tracking == r.tracking, last.floorId == r.floorId { continue }
            lastKept = r
            fr.t.append(ms(r.t)); fr.x.append(cm(r.x)); fr.y.append(cm(r.y)); fr.f.append(fi(r.floorId))
            fr.h.append(Int((r.headingRad * 1000).rounded())); fr.c.append(Int((r.confidence * 1000).rounded()))
            fr.loc.append(r.localized ? 1 : 0); fr.nh.append(r.hypotheses)
            fr.trk.append(r.tracking == nil ? 0 : (r.tracking == "lost" ? 2 : 1))
            if !track.isEmpty {
                let s = track.state(at: r.t)
                fr.tx.append(cm(s.x)); fr.ty.append(cm(s.y)); fr.tf.append(fi(s.floorId))
                fr.th.append(Int((s.headingRad * 1000).rounded()))
                fr.err.append(s.floorId == r.floorId ? cm(hypot(r.x - s.x, r.y - s.y)) : -1)
            }
        }
        frames = fr

        clouds = zip(result.particleTimeline, result.hypothesisTimeline).map { cloud, hyps in
            Cloud(t: ms(cloud.t),
                  p: cloud.particles.flatMap { [fi($0.floorId), cm($0.position.x), cm($0.position.y)] },
                  hyp: hyps.hypotheses.flatMap {
                      [fi($0.floorId), cm($0.positionInMap.x), cm($0.positionInMap.y), Int(($0.headingRad * 1000).rounded()),
                       Int(($0.weight * 1000).rounded()), cm($0.positionStdMeters)]
                  })
        }

        var events: [Event] = result.announcements.map { Event(t: ms($0.t), k: "said", text: $0.text) }
        events += result.trackingPrompts.map { Event(t: ms($0.t), k: "prompt", text: $0.text) }
        for h in result.haptics {
            let wrong = h.pattern == "wrongWay" || h.pattern == "offRoute"
            events.append(Event(t: ms(h.t), k: wrong ? "wrong" : "haptic", text: wrong ? Self.hapticText(h.pattern) : h.pattern))
        }
        for change in result.routeChanges where change.isReroute {
            let meters = zip(change.polyline, change.polyline.dropFirst()).reduce(0.0) { sum, pair in
                pair.0.floorId == pair.1.floorId ? sum + hypot(pair.1.point.x - pair.0.point.x, pair.1.point.y - pair.0.point.y) : sum
            }
            events.append(Event(t: ms(change.t), k: "reroute", text: String(format: "re-routed: %.0f m to go", meters)))
        }
        self.events = events.enumerated().sorted { ($0.element.t, $0.offset) < ($1.element.t, $1.offset) }.map(\.element)

        let rays = result.sightingRays
        let stride = max(1, (rays.count + Self.maximumSightings - 1) / Self.maximumSightings)
        sightings = rays.enumerated().compactMap { k, r in
            guard k % stride == 0 else { return nil }
            let floor = building.floor(id: r.floorId)
            let m = floor.flatMap { Self.matchingSign(kind: r.kind, camera: r.from, at: r.to, on: $0) }
            var truthMatch = ""
            if !track.isEmpty, let trueFloor = building.floor(id: track.state(at: r.t).floorId) {
                let s = track.state(at: r.t)
                let angle = s.headingRad + r.bearingRad
                let camera = Point2(x: s.x, y: s.y)
                let end = Point2(x: s.x + r.rangeMeters * cos(angle), y: s.y + r.rangeMeters * sin(angle))
                truthMatch = Self.matchingSign(kind: r.kind, camera: camera, at: end, on: trueFloor)?.sign.id ?? ""
            }
            return Sighting(t: ms(r.t), f: fi(r.floorId), x0: cm(r.from.x), y0: cm(r.from.y), x1: cm(r.to.x), y1: cm(r.to.y),
                            kind: r.kind, match: m?.sign.id ?? "", sx: cm(m?.sign.position.x ?? 0), sy: cm(m?.sign.position.y ?? 0),
                            md: cm(m?.distance ?? 0), truth: truthMatch)
        }

        routes = result.routeChanges.map { c in
            RouteView(t: ms(c.t), reroute: c.isReroute, p: c.polyline.flatMap { [fi($0.floorId), cm($0.point.x), cm($0.point.y)] })
        }

        var spells: [Spell] = []
        for (k, r) in result.trace.enumerated() {
            guard let tracking = r.tracking else { continue }
            let state = tracking == "lost" ? "lost" : "limited"
            let end = k + 1 < result.trace.count ? result.trace[k + 1].t : r.t
            if let last = spells.last, last.state == state, k > 0, result.trace[k - 1].tracking.map({ $0 == "lost" ? "lost" : "limited" }) == state {
                spells[spells.count - 1].t1 = ms(end)
            } else {
                spells.append(Spell(t0: ms(r.t), t1: ms(end), state: state, text: tracking))
            }
        }
        self.spells = spells

        let firstConvergence = result.trace.first(where: \.localized)?.t
        initial = ms(firstConvergence ?? (t0 + t1) / 2)
    }

    /// Words for a correction haptic.
    static func hapticText(_ pattern: String) -> String {
        switch pattern {
        case "wrongWay": return "wrong way (haptic)"
        case "offRoute": return "off route (haptic)"
        default: return pattern
        }
    }

    /// The sign of `kind` on `floor` nearest to `point` (where a sighting from `camera` puts the sign), within
    /// `matchRadiusMeters`, readable from the camera (facing it, or double-sided); nil when none.
    static func matchingSign(kind: String, camera: Point2, at point: Point2, on floor: Floor) -> (sign: Sign, distance: Double)? {
        var best: (sign: Sign, distance: Double)?
        for sign in floor.signs where sign.kind == kind {
            let toCamera = Point2(x: camera.x - sign.position.x, y: camera.y - sign.position.y)
            guard sign.doubleSided || toCamera.x * sign.facing.x + toCamera.y * sign.facing.y > 0 else { continue }
            let d = hypot(point.x - sign.position.x, point.y - sign.position.y)
            if d <= matchRadiusMeters, d < (best?.distance ?? .infinity) { best = (sign, d) }
        }
        return best
    }

    /// The JSON text, safe inside `<script type="application/json">`: `<`, `>` and `&` (which could close the
    /// element or open a comment) and the line separators U+2028/U+2029 become `\u` escapes. Outside strings
    /// JSON has none of these characters, so the document parses to the same value.
    func scriptSafeJSON() -> String {
        let encoder = JSONEncoder()
        encoder.outputFormatting = [.sortedKeys]
        let data = (try? encoder.encode(self)) ?? Data("{}".utf8)
        var out = ""
        out.reserveCapacity(data.count + 64)
        for c in String(decoding: data, as: UTF8.self).unicodeScalars {
            switch c {
            case "<": out += "\\u003c"
            case ">": out += "\\u003e"
            case "&": out += "\\u0026"
            case "\u{2028}": out += "\\u2028"
            case "\u{2029}": out += "\\u2029"
            default: out.unicodeScalars.append(c)
            }
        }
        return out
    }
}
