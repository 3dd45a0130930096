import Foundation
import Maps
import SessionFormat
import WayfinderCore

/// The trainer's picture of a walk: one static, self-contained HTML page (inline SVG, CSS and a few lines of
/// JavaScript, no external resources) showing per floor the plan (walls, doors, signs with facing arrows,
/// graph), the true path, the estimate coloured by error, particle clouds at chosen moments, sign sightings
/// as rays, and the announcements numbered where they were spoken, plus a timeline, summary figures and an
/// announcements table for screen readers.
public enum WalkReport {
    /// Error colour bands, meters: green below the first, yellow below the second, red above.
    public static let errorBandsMeters = (good: 0.5, fair: 1.5)

    /// Builds the HTML page.
    public static func html(title: String, building: Building, result: ReplayResult, truth: [TruthRecord],
                            score: WalkScore?) -> String {
        let track = TruthTrack(truth)
        let floors = building.floors.filter { f in
            result.trace.contains { $0.floorId == f.id } || truth.contains { $0.floorId == f.id }
        }
        var body = ""
        body += "<h1>\(escape(title))</h1>\n"
        body += "<p class=\"sub\">\(escape(building.name)) · \(result.trace.count) frames · "
        body += String(format: "%.0f s", (result.trace.last?.t ?? 0) - (result.trace.first?.t ?? 0)) + "</p>\n"
        if let score { body += summary(score) }
        body += legend()
        // Floor switching: the buttons and sections carry the floor's index (never its id) in data-floor, and one
        // fixed script (floorScript) reads it; no script text is ever built from map data.
        let shown = floors.isEmpty ? Array(building.floors.prefix(1)) : floors
        if floors.count > 1 {
            body += "<nav aria-label=\"Floors\">" + floors.enumerated().map { i, f in
                "<button type=\"button\" data-floor=\"\(i)\" aria-controls=\"floor-section-\(i)\">\(escape(f.name))</button>"
            }.joined() + "</nav>\n"
        }
        for (i, floor) in shown.enumerated() {
            body += "<section id=\"floor-section-\(i)\" data-floor=\"\(i)\" data-floor-id=\"\(escape(floor.id))\" class=\"floor\" style=\"display:\(i == 0 ? "block" : "none")\">"
            body += "<h2>\(escape(floor.name))</h2>"
            body += floorSVG(floor: floor, building: building, result: result, track: track)
            body += "</section>\n"
        }
        body += timeline(result: result, track: track)
        body += announcementTable(result: result, track: track)
        return """
        <!DOCTYPE html>
        <html lang="en"><head><meta charset="utf-8"><title>\(escape(title))</title>
        <style>
        body{font:14px/1.4 "DejaVu Sans",Helvetica,Arial,sans-serif;margin:16px 24px;color:#222;background:#fff}
        h1{font-size:22px;margin:0 0 2px} h2{font-size:16px;margin:10px 0 4px} .sub{color:#666;margin:0 0 8px}
        .figs{display:flex;flex-wrap:wrap;gap:8px;margin:6px 0} .fig{border:1px solid #ddd;border-radius:6px;padding:4px 10px}
        .fig b{display:block;font-size:18px} .legend span{margin-right:14px;white-space:nowrap}
        .sw{display:inline-block;width:22px;height:4px;vertical-align:middle;margin-right:4px}
        svg{border:1px solid #ccc;background:#fbfbf8} table{border-collapse:collapse;margin-top:8px}
        td,th{border:1px solid #ddd;padding:2px 8px;text-align:left} nav button{margin-right:6px}
        </style>
        </head><body>
        \(body)
        \(floorScript)
        </body></html>
        """
    }

    /// The page's only script, a constant: clicking a floor button shows the section with the same
    /// `data-floor` index. Map data never becomes script text (no inline handlers, no generated code).
    static let floorScript = """
        <script>
        document.querySelectorAll('nav button[data-floor]').forEach(function (b) {
          b.addEventListener('click', function () {
            var k = b.getAttribute('data-floor');
            document.querySelectorAll('section.floor').forEach(function (s) {
              s.style.display = s.getAttribute('data-floor') === k ? 'block' : 'none';
            });
          });
        });
        </script>
        """

    /// Escapes text for HTML element content and for quoted attribute values (either quote): `&`, `<`, `>`,
    /// `"` and `'` become character references. Not for script or style contexts (nothing from data goes there).
    static func escape(_ s: String) -> String {
        var out = ""
        out.reserveCapacity(s.utf8.count)
        for c in s.unicodeScalars {
            switch c {
            case "&": out += "&amp;"
            case "<": out += "&lt;"
            case ">": out += "&gt;"
            case "\"": out += "&quot;"
            case "'": out += "&#39;"
            default: out.unicodeScalars.append(c)
            }
        }
        return out
    }

    static func summary(_ s: WalkScore) -> String {
        func f(_ v: Double?, _ unit: String, _ d: Int = 2) -> String { v.map { String(format: "%.\(d)f %@", $0, unit) } ?? "never" }
        let l = s.localization, n = s.navigation
        let items: [(String, String)] = [
            ("converged after", f(l.distanceToConvergenceMeters, "m", 1) + (l.timeToConvergenceSeconds.map { String(format: " / %.0f s", $0) } ?? "")),
            ("median error", f(l.medianErrorMeters, "m")), ("95th pct error", f(l.p95ErrorMeters, "m")),
            ("heading error", f(l.medianHeadingErrorDeg, "°", 1)),
            ("localized", String(format: "%.0f %% of time", l.fractionLocalized * 100)),
            ("confidently wrong", "\(l.wrongConvergenceEpisodes) times"),
            ("turns cued", "\(n.cueDistancesBeforeMeters.count) of \(n.expectedTurns.count)"),
            ("cue before point", f(percentile(n.cueDistancesBeforeMeters, 50), "m")),
            ("arrival", n.arrivalAnnounced ? f(n.arrivalDistanceMeters, "m from target") : "not announced"),
        ]
        return "<div class=\"figs\" role=\"list\" aria-label=\"Summary figures\">" + items.map {
            "<div class=\"fig\" role=\"listitem\">\(escape($0.0))<b>\(escape($0.1))</b></div>"
        }.joined() + "</div>\n"
    }

    static func legend() -> String {
        """
        <p class="legend"><span><i class="sw" style="background:#1f4e9c"></i>true path</span>\
        <span><i class="sw" style="background:#2a9d3f"></i>estimate &lt; 0.5 m</span>\
        <span><i class="sw" style="background:#e0b000"></i>&lt; 1.5 m</span>\
        <span><i class="sw" style="background:#d22"></i>worse</span>\
        <span><i class="sw" style="background:#aaa"></i>not localized (dots)</span>\
        <span><i class="sw" style="background:#c060c0"></i>sign sighting</span>\
        <span><i class="sw" style="background:#0a0;height:8px;width:10px"></i>Exit sign (line: facing)</span><span>● particles</span><span>① announcement</span></p>

        """
    }

    static func errorColor(_ record: TraceRecord, _ track: TruthTrack) -> String {
        guard record.localized else { return "#aaa" }
        guard !track.isEmpty else { return "#2a9d3f" }
        let s = track.state(at: record.t)
        guard s.floorId == record.floorId else { return "#d22" }
        let e = hypot(record.x - s.x, record.y - s.y)
        return e < errorBandsMeters.good ? "#2a9d3f" : (e < errorBandsMeters.fair ? "#e0b000" : "#d22")
    }

    static func floorSVG(floor: Floor, building: Building, result: ReplayResult, track: TruthTrack) -> String {
        var minX = Double.infinity, minY = Double.infinity, maxX = -Double.infinity, maxY = -Double.infinity
        for w in floor.walls { for p in [w.from, w.to] { minX = min(minX, p.x); maxX = max(maxX, p.x); minY = min(minY, p.y); maxY = max(maxY, p.y) } }
        if !minX.isFinite { minX = 0; minY = 0; maxX = 10; maxY = 10 }
        let margin = 1.0
        let widthM = maxX - minX + 2 * margin, heightM = maxY - minY + 2 * margin
        let scale = min(1300 / widthM, 760 / heightM)
        let w = widthM * scale, h = heightM * scale
        func X(_ x: Double) -> String { String(format: "%.1f", (x - minX + margin) * scale) }
        func Y(_ y: Double) -> String { String(format: "%.1f", (maxY + margin - y) * scale) }
        var s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"\(Int(w))\" height=\"\(Int(h))\" role=\"img\" aria-label=\"Floor plan of \(escape(floor.name)) with the walk\">"
        // Graph
        let nodes = Dictionary(building.graph.nodes.map { ($0.id, $0) }, uniquingKeysWith: { a, _ in a })
        for e in building.graph.edges {
            guard let a = nodes[e.from], let b = nodes[e.to], a.floorId == floor.id, b.floorId == floor.id else { continue }
            s += "<line x1=\"\(X(a.position.x))\" y1=\"\(Y(a.position.y))\" x2=\"\(X(b.position.x))\" y2=\"\(Y(b.position.y))\" stroke=\"#cfd8e8\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>"
        }
        // Walls
        s += "<g stroke=\"#333\" stroke-width=\"2\" stroke-linecap=\"round\">"
        for wall in floor.walls {
            s += "<line x1=\"\(X(wall.from.x))\" y1=\"\(Y(wall.from.y))\" x2=\"\(X(wall.to.x))\" y2=\"\(Y(wall.to.y))\"/>"
        }
        s += "</g>"
        for d in floor.doors {
            s += "<circle cx=\"\(X(d.position.x))\" cy=\"\(Y(d.position.y))\" r=\"3\" fill=\"#8b5a2b\"><title>door \(escape(d.label ?? d.id))</title></circle>"
        }
        for p in floor.pointsOfInterest {
            s += "<text x=\"\(X(p.position.x))\" y=\"\(Y(p.position.y))\" font-size=\"10\" fill=\"#557\" text-anchor=\"middle\">\(escape(p.name))</text>"
        }
        // Particle clouds (the last snapshot drawn on top)
        let palette = ["#7f7fff", "#ff9f40", "#40c0c0", "#c0c040", "#ff6fa0", "#60a060"]
        for (i, snap) in result.particleSnapshots.enumerated() {
            let color = palette[i % palette.count]
            s += "<g fill=\"\(color)\" fill-opacity=\"0.35\"><title>particles at \(escape(snap.label)) (t=\(String(format: "%.1f", snap.t)) s)</title>"
            for p in snap.particles where p.floorId == floor.id {
                s += "<circle cx=\"\(X(p.position.x))\" cy=\"\(Y(p.position.y))\" r=\"1.3\"/>"
            }
            s += "</g>"
        }
        // Sighting rays (subsampled to keep the file small)
        let rays = result.sightingRays.filter { $0.floorId == floor.id }
        let stride = max(1, rays.count / 300)
        s += "<g stroke=\"#c060c0\" stroke-width=\"1\" stroke-opacity=\"0.5\">"
        for (i, r) in rays.enumerated() where i % stride == 0 {
            s += "<line x1=\"\(X(r.from.x))\" y1=\"\(Y(r.from.y))\" x2=\"\(X(r.to.x))\" y2=\"\(Y(r.to.y))\"/>"
        }
        s += "</g>"
        // Signs
        for sign in floor.signs {
            let tip = Point2(x: sign.position.x + 0.8 * sign.facing.x, y: sign.position.y + 0.8 * sign.facing.y)
            s += "<line x1=\"\(X(sign.position.x))\" y1=\"\(Y(sign.position.y))\" x2=\"\(X(tip.x))\" y2=\"\(Y(tip.y))\" stroke=\"#0a0\" stroke-width=\"2\"/>"
            s += "<rect x=\"\(String(format: "%.1f", (sign.position.x - minX + margin) * scale - 5))\" y=\"\(String(format: "%.1f", (maxY + margin - sign.position.y) * scale - 4))\" width=\"10\" height=\"8\" fill=\"#0a0\"><title>\(escape(sign.kind)) sign \(escape(sign.id))</title></rect>"
        }
        // True path
        let truthPoints = track.records.filter { $0.floorId == floor.id }.map { "\(X($0.x)),\(Y($0.y))" }
        if !truthPoints.isEmpty {
            s += "<polyline points=\"\(truthPoints.joined(separator: " "))\" fill=\"none\" stroke=\"#1f4e9c\" stroke-width=\"3\" stroke-opacity=\"0.7\"/>"
        }
        // Estimate coloured by error; while not localized the estimate jumps between hypotheses, so it is
        // drawn as faint dots rather than a line.
        let allEstimates = result.trace.filter { $0.floorId == floor.id }
        s += "<g fill=\"#999\" fill-opacity=\"0.5\"><title>estimate while not localized</title>"
        for (k, r) in allEstimates.enumerated() where !r.localized && k % 3 == 0 {
            s += "<circle cx=\"\(X(r.x))\" cy=\"\(Y(r.y))\" r=\"1.5\"/>"
        }
        s += "</g>"
        let est = allEstimates.filter(\.localized)
        var i = 0
        while i + 1 < est.count {
            let color = errorColor(est[i], track)
            var j = i + 1
            var pts = ["\(X(est[i].x)),\(Y(est[i].y))"]
            while j < est.count, errorColor(est[j], track) == color, hypot(est[j].x - est[j - 1].x, est[j].y - est[j - 1].y) < 3 {
                pts.append("\(X(est[j].x)),\(Y(est[j].y))"); j += 1
            }
            if j < est.count { pts.append("\(X(est[j].x)),\(Y(est[j].y))") }
            s += "<polyline points=\"\(pts.joined(separator: " "))\" fill=\"none\" stroke=\"\(color)\" stroke-width=\"2\"/>"
            i = j
        }
        // Announcements where they were spoken (at the true position if known, else the estimate)
        for (n, a) in result.announcements.enumerated() {
            let p: (x: Double, y: Double, f: String)
            if !track.isEmpty { let t = track.state(at: a.t); p = (t.x, t.y, t.floorId) } else {
                guard let r = result.trace.last(where: { $0.t <= a.t }) else { continue }
                p = (r.x, r.y, r.floorId)
            }
            guard p.f == floor.id else { continue }
            s += "<g><circle cx=\"\(X(p.x))\" cy=\"\(Y(p.y))\" r=\"8\" fill=\"#fff\" stroke=\"#000\"/><text x=\"\(X(p.x))\" y=\"\(Y(p.y))\" dy=\"3.5\" font-size=\"9\" text-anchor=\"middle\">\(n + 1)</text><title>\(escape(a.text))</title></g>"
        }
        s += "</svg>"
        return s
    }

    static func timeline(result: ReplayResult, track: TruthTrack) -> String {
        guard let t0 = result.trace.first?.t, let t1 = result.trace.last?.t, t1 > t0 else { return "" }
        let width = 1300.0
        func X(_ t: Double) -> String { String(format: "%.1f", 10 + (t - t0) / (t1 - t0) * (width - 20)) }
        var s = "<h2>Timeline</h2><svg width=\"\(Int(width))\" height=\"70\" role=\"img\" aria-label=\"Timeline of localization and announcements\">"
        for (i, r) in result.trace.enumerated() where i + 1 < result.trace.count {
            let next = result.trace[i + 1]
            s += "<rect x=\"\(X(r.t))\" y=\"10\" width=\"\(String(format: "%.2f", max(0.5, (next.t - r.t) / (t1 - t0) * (width - 20))))\" height=\"14\" fill=\"\(errorColor(r, track))\"/>"
        }
        for (n, a) in result.announcements.enumerated() {
            s += "<g><line x1=\"\(X(a.t))\" x2=\"\(X(a.t))\" y1=\"26\" y2=\"44\" stroke=\"#000\"/><text x=\"\(X(a.t))\" y=\"56\" font-size=\"10\" text-anchor=\"middle\">\(n + 1)</text><title>\(escape(a.text))</title></g>"
        }
        s += "<text x=\"10\" y=\"68\" font-size=\"10\">\(String(format: "%.0f s", t0))</text><text x=\"\(Int(width - 10))\" y=\"68\" font-size=\"10\" text-anchor=\"end\">\(String(format: "%.0f s", t1))</text></svg>\n"
        return s
    }

    static func announcementTable(result: ReplayResult, track: TruthTrack) -> String {
        var s = "<h2>Announcements</h2><table><thead><tr><th>#</th><th>time</th><th>said</th><th>true position</th></tr></thead><tbody>"
        for (n, a) in result.announcements.enumerated() {
            let pos: String
            if track.isEmpty { pos = "-" } else { let t = track.state(at: a.t); pos = String(format: "(%.1f, %.1f) floor %@", t.x, t.y, t.floorId) }
            s += "<tr><td>\(n + 1)</td><td>\(String(format: "%.1f s", a.t))</td><td>\(escape(a.text))</td><td>\(escape(pos))</td></tr>"
        }
        s += "</tbody></table>\n"
        return s
    }
}
