import Foundation
import Maps
import SessionFormat
import WayfinderCore

/// The trainer's view of a walk: one self-contained HTML page (inline SVG, CSS, one constant script; nothing
/// fetched) with, per floor, the plan (walls, doors, signs with facing arrows, graph), the true path and the
/// estimate coloured by error, and a moving layer driven by a playhead: a timeline (error band, tracking
/// spells, confidence, what was said and felt, sightings, wrong turns and re-routes) with a scrubber and Play.
/// At the playhead the plan shows the true and estimated positions, the particle cloud and hypotheses, the
/// sightings with the sign each matched, and the route in force; a panel gives the state in words. The walk's
/// data goes into the page as JSON (`WalkViewData`, never as script); the script is `WalkViewScript.source`.
/// An announcements table serves screen readers.
public enum WalkReport {
    /// Error colour bands, meters: green below the first, yellow below the second, red above.
    public static let errorBandsMeters = (good: 0.5, fair: 1.5)
    /// Colours of the particle clouds kept at chosen moments (start, first convergence, middle, end, --at).
    static let snapshotPalette = ["#7f7fff", "#ff9f40", "#40c0c0", "#c0c040", "#ff6fa0", "#60a060"]
    /// Timeline width and its label column, pixels.
    static let timelineWidth = 1300.0, timelineLeft = 90.0

    /// Builds the HTML page. For the moving layer `result` needs `particleTimeline` (replay with
    /// `Options.particleTimelineIntervalSeconds`); without it the plan shows no cloud at the playhead.
    public static func html(title: String, building: Building, result: ReplayResult, truth: [TruthRecord],
                            score: WalkScore?) -> String {
        let track = TruthTrack(truth)
        let floors = building.floors.filter { f in
            result.trace.contains { $0.floorId == f.id } || truth.contains { $0.floorId == f.id }
        }
        let shown = floors.isEmpty ? Array(building.floors.prefix(1)) : floors
        let data = WalkViewData(building: building, floors: shown, result: result, track: track,
                                timelineWidth: timelineWidth, timelineLeft: timelineLeft)
        var body = ""
        body += "<h1>\(escape(title))</h1>\n"
        body += "<p class=\"sub\">\(escape(building.name)) · \(result.trace.count) frames · "
        body += String(format: "%.0f s", (result.trace.last?.t ?? 0) - (result.trace.first?.t ?? 0)) + "</p>\n"
        if let score { body += summary(score) }
        body += player(result: result)
        body += legend(result: result, hasTruth: !track.isEmpty)
        // Floor switching: the buttons and sections carry the floor's index (never its id) in data-floor, and the
        // one fixed script reads it; no script text is ever built from map data.
        if shown.count > 1 {
            body += "<nav aria-label=\"Floors\">" + shown.enumerated().map { i, f in
                "<button type=\"button\" data-floor=\"\(i)\" aria-controls=\"floor-section-\(i)\">\(escape(f.name))</button>"
            }.joined() + "</nav>\n"
        }
        for (i, floor) in shown.enumerated() {
            body += "<section id=\"floor-section-\(i)\" data-floor=\"\(i)\" data-floor-id=\"\(escape(floor.id))\" class=\"floor\" style=\"display:\(i == 0 ? "block" : "none")\">"
            body += "<h2>\(escape(floor.name))</h2>"
            body += floorSVG(floor: floor, index: i, building: building, result: result, track: track)
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
        .fig b{display:block;font-size:18px} .legend{display:flex;flex-wrap:wrap;gap:4px 14px;margin:6px 0}
        .legend span{white-space:nowrap} .legend svg{border:0;background:none;vertical-align:middle;margin-right:4px}
        svg{border:1px solid #ccc;background:#fbfbf8} table{border-collapse:collapse;margin-top:8px}
        td,th{border:1px solid #ddd;padding:2px 8px;text-align:left} nav button{margin-right:6px}
        .player{display:flex;align-items:center;gap:10px;margin:8px 0} #scrubber{width:700px}
        .state{display:grid;grid-template-columns:max-content 1fr max-content 1fr;gap:2px 12px;margin:4px 0 8px;max-width:1300px}
        .state dt{color:#666} .state dd{margin:0}
        g.cloud circle{fill:#4b2c8f;fill-opacity:0.45} g.hyp circle{fill:none;stroke:#4b2c8f;stroke-dasharray:3 2}
        line.ray{stroke:#c060c0;stroke-width:2} circle.matched{fill:none;stroke:#0a0;stroke-width:2.5}
        polyline.route{fill:none;stroke:#20a0a0;stroke-width:5;stroke-opacity:0.35}
        g.est circle{stroke:#000;stroke-width:1.5} g.est.localized circle{fill:#2a9d3f} g.est.searching circle{fill:#aaa}
        g.est line, g.truth line{stroke-width:2} g.est line{stroke:#000} g.truth circle{fill:none;stroke:#1f4e9c;stroke-width:3} g.truth line{stroke:#1f4e9c}
        </style>
        </head><body>
        \(body)
        <script type="application/json" id="walk-data">\(data.scriptSafeJSON())</script>
        \(WalkViewScript.source)
        </body></html>
        """
    }

    /// The playhead controls and the state panel the script fills in (initial text for a page without script).
    static func player(result: ReplayResult) -> String {
        let t0 = result.trace.first?.t ?? 0, t1 = result.trace.last?.t ?? 0
        let initial = result.trace.first(where: \.localized)?.t ?? (t0 + t1) / 2
        func f(_ v: Double) -> String { String(format: "%.1f", v) }
        var s = "<div class=\"player\" role=\"group\" aria-label=\"Playhead\">"
        s += "<button type=\"button\" id=\"play\" aria-pressed=\"false\">Play</button>"
        s += "<label for=\"scrubber\">Time</label><input type=\"range\" id=\"scrubber\" min=\"\(f(t0))\" max=\"\(f(t1))\" step=\"0.1\" value=\"\(f(initial))\">"
        s += "<label for=\"speed\">Speed</label><select id=\"speed\"><option value=\"1\">1x</option><option value=\"2\">2x</option><option value=\"4\" selected>4x</option><option value=\"10\">10x</option></select>"
        s += "<label><input type=\"checkbox\" id=\"show-snapshots\"> clouds at chosen moments</label></div>\n"
        let items: [(String, String)] = [("time", "st-time"), ("confidence", "st-conf"), ("localizer", "st-loc"),
                                         ("hypotheses", "st-hyp"), ("tracking", "st-track"), ("error", "st-err"),
                                         ("said", "st-said"), ("felt", "st-felt"), ("sightings", "st-sight"),
                                         ("wrong turns, re-routes", "st-nav")]
        s += "<dl class=\"state\" aria-label=\"State at the playhead\">"
        for (label, id) in items {
            s += "<dt>\(label)</dt><dd id=\"\(id)\">-</dd>"
            if id == "st-conf" { s.removeLast(5); s += " <meter id=\"st-conf-bar\" min=\"0\" max=\"1\" value=\"0\"></meter></dd>" }
        }
        s += "</dl>\n"
        return s
    }

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

    /// The legend: one entry per kind of mark drawn, each with a swatch drawn the way the plan draws it
    /// (same shapes, colours and CSS classes), and one entry per cloud kept at a chosen moment with its colour.
    static func legend(result: ReplayResult, hasTruth: Bool) -> String {
        func swatch(_ inner: String) -> String {
            "<svg width=\"26\" height=\"16\" viewBox=\"0 0 26 16\" aria-hidden=\"true\">\(inner)</svg>"
        }
        var items: [(String, String)] = []
        if hasTruth {
            items.append((swatch("<line x1=\"1\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#1f4e9c\" stroke-width=\"3\" stroke-opacity=\"0.7\"/>"), "true path"))
            items.append((swatch("<g class=\"truth\" transform=\"translate(11,8)\"><circle r=\"6\"/><line x1=\"0\" y1=\"0\" x2=\"13\" y2=\"0\"/></g>"), "true position now (line: heading)"))
        }
        items += [
            (swatch("<line x1=\"1\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#2a9d3f\" stroke-width=\"2\"/>"), "estimate, error < 0.5 m" + (hasTruth ? "" : " (no truth: localized)")),
        ]
        if hasTruth {
            items.append((swatch("<line x1=\"1\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#e0b000\" stroke-width=\"2\"/>"), "error < 1.5 m"))
            items.append((swatch("<line x1=\"1\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#d22\" stroke-width=\"2\"/>"), "error >= 1.5 m or wrong floor"))
        }
        items += [
            (swatch("<g fill=\"#999\" fill-opacity=\"0.5\"><circle cx=\"5\" cy=\"8\" r=\"1.5\"/><circle cx=\"13\" cy=\"8\" r=\"1.5\"/><circle cx=\"21\" cy=\"8\" r=\"1.5\"/></g>"), "estimate while not localized"),
            (swatch("<g class=\"est localized\" transform=\"translate(11,8)\"><circle r=\"5\"/><line x1=\"0\" y1=\"0\" x2=\"13\" y2=\"0\"/></g>"), "estimate now (grey: searching)"),
            (swatch("<g class=\"cloud\"><circle cx=\"5\" cy=\"6\" r=\"1.6\"/><circle cx=\"11\" cy=\"10\" r=\"1.6\"/><circle cx=\"17\" cy=\"5\" r=\"1.6\"/><circle cx=\"21\" cy=\"11\" r=\"1.6\"/></g>"), "particles now"),
            (swatch("<g class=\"hyp\"><circle cx=\"13\" cy=\"8\" r=\"6\" stroke-width=\"2\"/></g>"), "hypothesis (size: spread, line: weight)"),
            (swatch("<line class=\"ray\" x1=\"1\" y1=\"12\" x2=\"25\" y2=\"4\"/>"), "sign sighting in the last second"),
            (swatch("<circle class=\"matched\" cx=\"13\" cy=\"8\" r=\"6\"/><rect x=\"9\" y=\"5\" width=\"8\" height=\"6\" fill=\"#0a0\"/>"), "sign it matched"),
            (swatch("<rect x=\"8\" y=\"4\" width=\"10\" height=\"8\" fill=\"#0a0\"/><line x1=\"13\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#0a0\" stroke-width=\"2\"/>"), "sign (line: facing)"),
            (swatch("<polyline class=\"route\" points=\"1,8 25,8\"/>"), "route in force"),
            (swatch("<line x1=\"1\" y1=\"8\" x2=\"25\" y2=\"8\" stroke=\"#cfd8e8\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>"), "graph"),
            (swatch("<circle cx=\"13\" cy=\"8\" r=\"3\" fill=\"#8b5a2b\"/>"), "door"),
            (swatch("<circle cx=\"13\" cy=\"8\" r=\"7\" fill=\"#fff\" stroke=\"#000\"/><text x=\"13\" y=\"8\" dy=\"3.5\" font-size=\"9\" text-anchor=\"middle\">1</text>"), "announcement, where it was said"),
        ]
        for (i, snap) in result.particleSnapshots.enumerated() {
            let color = snapshotPalette[i % snapshotPalette.count]
            items.append((swatch("<g fill=\"\(color)\" fill-opacity=\"0.6\"><circle cx=\"6\" cy=\"7\" r=\"2\"/><circle cx=\"13\" cy=\"10\" r=\"2\"/><circle cx=\"20\" cy=\"6\" r=\"2\"/></g>"),
                          "particles at \(snap.label) (\(String(format: "%.1f", snap.t)) s, shown with the checkbox)"))
        }
        return "<div class=\"legend\" role=\"list\" aria-label=\"Legend\">" + items.map { "<span role=\"listitem\" class=\"legend-item\">\($0.0)\(escape($0.1))</span>" }.joined() + "</div>\n"
    }

    static func errorColor(_ record: TraceRecord, _ track: TruthTrack) -> String {
        guard record.localized else { return "#aaa" }
        guard !track.isEmpty else { return "#2a9d3f" }
        let s = track.state(at: record.t)
        guard s.floorId == record.floorId else { return "#d22" }
        let e = hypot(record.x - s.x, record.y - s.y)
        return e < errorBandsMeters.good ? "#2a9d3f" : (e < errorBandsMeters.fair ? "#e0b000" : "#d22")
    }

    static func floorSVG(floor: Floor, index: Int, building: Building, result: ReplayResult, track: TruthTrack) -> String {
        let frame = FloorFrame(floor: floor)
        func X(_ x: Double) -> String { frame.X(x) }
        func Y(_ y: Double) -> String { frame.Y(y) }
        var s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"\(Int(frame.w))\" height=\"\(Int(frame.h))\" role=\"img\" aria-label=\"Floor plan of \(escape(floor.name)) with the walk\">"
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
        // The route in force at the playhead (points set by the script).
        s += "<polyline class=\"route\" id=\"live-route-\(index)\" points=\"\"/>"
        // Particle clouds kept at chosen moments: hidden until the checkbox shows them.
        for (i, snap) in result.particleSnapshots.enumerated() {
            let color = snapshotPalette[i % snapshotPalette.count]
            s += "<g class=\"snapshot\" style=\"display:none\" fill=\"\(color)\" fill-opacity=\"0.35\"><title>particles at \(escape(snap.label)) (t=\(String(format: "%.1f", snap.t)) s)</title>"
            for p in snap.particles where p.floorId == floor.id {
                s += "<circle cx=\"\(X(p.position.x))\" cy=\"\(Y(p.position.y))\" r=\"1.3\"/>"
            }
            s += "</g>"
        }
        // Signs
        for sign in floor.signs {
            let tip = Point2(x: sign.position.x + 0.8 * sign.facing.x, y: sign.position.y + 0.8 * sign.facing.y)
            s += "<line x1=\"\(X(sign.position.x))\" y1=\"\(Y(sign.position.y))\" x2=\"\(X(tip.x))\" y2=\"\(Y(tip.y))\" stroke=\"#0a0\" stroke-width=\"2\"/>"
            s += "<rect x=\"\(String(format: "%.1f", (sign.position.x + frame.ox) * frame.s - 5))\" y=\"\(String(format: "%.1f", (frame.oy - sign.position.y) * frame.s - 4))\" width=\"10\" height=\"8\" fill=\"#0a0\"><title>\(escape(sign.kind)) sign \(escape(sign.id))</title></rect>"
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
        // The moving layer: filled and placed by the script at the playhead.
        s += "<g class=\"cloud\" id=\"live-cloud-\(index)\"></g><g class=\"hyp\" id=\"live-hyp-\(index)\"></g><g id=\"live-rays-\(index)\"></g>"
        s += "<g class=\"truth\" id=\"live-truth-\(index)\" style=\"display:none\"><circle r=\"7\"/><line x1=\"0\" y1=\"0\" x2=\"16\" y2=\"0\"/><title>true position</title></g>"
        s += "<g class=\"est searching\" id=\"live-est-\(index)\" style=\"display:none\"><circle r=\"5.5\"/><line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\"/><title>estimate</title></g>"
        s += "</svg>"
        return s
    }

    /// The timeline: labelled rows under one time axis, and the playhead (moved by the script; a click or drag
    /// on the timeline moves it too).
    static func timeline(result: ReplayResult, track: TruthTrack) -> String {
        guard let t0 = result.trace.first?.t, let t1 = result.trace.last?.t, t1 > t0 else { return "" }
        let width = timelineWidth, left = timelineLeft
        func xv(_ t: Double) -> Double { left + (t - t0) / (t1 - t0) * (width - left - 10) }
        func X(_ t: Double) -> String { String(format: "%.1f", xv(t)) }
        let rows: [(label: String, y: Double)] = [("estimate", 10), ("tracking", 30), ("confidence", 50), ("said", 78),
                                                  ("felt", 100), ("sightings", 118), ("wrong, route", 136)]
        var s = "<h2>Timeline</h2><svg id=\"timeline\" width=\"\(Int(width))\" height=\"170\" role=\"img\" aria-label=\"Timeline: localization, tracking, confidence, speech, haptics, sightings, corrections; click or drag to move the playhead\" style=\"cursor:pointer;touch-action:none\">"
        for r in rows { s += "<text x=\"4\" y=\"\(Int(r.y) + 11)\" font-size=\"10\" fill=\"#555\">\(r.label)</text>" }
        // Estimate band, one rectangle per run of one colour.
        var k = 0
        while k < result.trace.count {
            let color = errorColor(result.trace[k], track)
            var j = k + 1
            while j < result.trace.count, errorColor(result.trace[j], track) == color { j += 1 }
            let end = j < result.trace.count ? result.trace[j].t : t1
            s += "<rect x=\"\(X(result.trace[k].t))\" y=\"10\" width=\"\(String(format: "%.2f", max(0.5, xv(end) - xv(result.trace[k].t))))\" height=\"14\" fill=\"\(color)\"/>"
            k = j
        }
        // Tracking spells.
        var k2 = 0
        while k2 < result.trace.count {
            guard let state = result.trace[k2].tracking else { k2 += 1; continue }
            let lost = state == "lost"
            var j = k2 + 1
            while j < result.trace.count, let next = result.trace[j].tracking, (next == "lost") == lost { j += 1 }
            let end = j < result.trace.count ? result.trace[j].t : t1
            s += "<rect x=\"\(X(result.trace[k2].t))\" y=\"30\" width=\"\(String(format: "%.2f", max(1, xv(end) - xv(result.trace[k2].t))))\" height=\"14\" fill=\"\(lost ? "#802020" : "#f0a030")\"><title>tracking \(escape(state)) \(String(format: "%.1f-%.1f s", result.trace[k2].t, end))</title></rect>"
            k2 = j
        }
        // Confidence, 0 at the bottom of its row, 1 at the top.
        var conf: [String] = []
        var lastT = -Double.infinity
        for r in result.trace where r.t - lastT >= 0.2 { lastT = r.t; conf.append("\(X(r.t)),\(String(format: "%.1f", 72 - 22 * r.confidence))") }
        s += "<line x1=\"\(Int(left))\" x2=\"\(Int(width - 10))\" y1=\"72\" y2=\"72\" stroke=\"#ddd\"/><polyline points=\"\(conf.joined(separator: " "))\" fill=\"none\" stroke=\"#4b2c8f\" stroke-width=\"1.5\"/>"
        // Said: announcements (numbered) and tracking prompts.
        for (n, a) in result.announcements.enumerated() {
            s += "<g><line x1=\"\(X(a.t))\" x2=\"\(X(a.t))\" y1=\"78\" y2=\"90\" stroke=\"#000\"/><text x=\"\(X(a.t))\" y=\"99\" font-size=\"8\" text-anchor=\"middle\">\(n + 1)</text><title>\(String(format: "%.1f s", a.t)): \(escape(a.text))</title></g>"
        }
        for p in result.trackingPrompts {
            s += "<g><line x1=\"\(X(p.t))\" x2=\"\(X(p.t))\" y1=\"78\" y2=\"92\" stroke=\"#f07000\" stroke-width=\"2\"/><title>\(String(format: "%.1f s", p.t)) tracking prompt: \(escape(p.text))</title></g>"
        }
        // Felt: haptics (corrections in red).
        for h in result.haptics {
            let wrong = h.pattern == "wrongWay" || h.pattern == "offRoute"
            s += "<g><circle cx=\"\(X(h.t))\" cy=\"106\" r=\"3\" fill=\"\(wrong ? "#d22" : "#8040c0")\"/><title>\(String(format: "%.1f s", h.t)) haptic \(escape(h.pattern))</title></g>"
        }
        // Sightings (at most one tick per pixel column).
        var lastColumn = -1
        for r in result.sightingRays {
            let column = Int(xv(r.t))
            guard column != lastColumn else { continue }
            lastColumn = column
            s += "<line x1=\"\(column)\" x2=\"\(column)\" y1=\"118\" y2=\"130\" stroke=\"#c060c0\"/>"
        }
        // Wrong turns (corrections) and re-routes.
        for h in result.haptics where h.pattern == "wrongWay" || h.pattern == "offRoute" {
            let x = xv(h.t)
            s += "<g><path d=\"M\(String(format: "%.1f", x - 5)),148 L\(String(format: "%.1f", x + 5)),148 L\(String(format: "%.1f", x)),138 Z\" fill=\"#d22\"/><title>\(String(format: "%.1f s", h.t)) \(escape(WalkViewData.hapticText(h.pattern)))</title></g>"
        }
        for c in result.routeChanges where c.isReroute {
            let x = xv(c.t)
            s += "<g><path d=\"M\(String(format: "%.1f", x)),137 L\(String(format: "%.1f", x + 5)),143 L\(String(format: "%.1f", x)),149 L\(String(format: "%.1f", x - 5)),143 Z\" fill=\"#20a0a0\"/><title>\(String(format: "%.1f s", c.t)) re-route</title></g>"
        }
        s += "<text x=\"\(Int(left))\" y=\"164\" font-size=\"10\">\(String(format: "%.0f s", t0))</text><text x=\"\(Int(width - 10))\" y=\"164\" font-size=\"10\" text-anchor=\"end\">\(String(format: "%.0f s", t1))</text>"
        let initial = result.trace.first(where: \.localized)?.t ?? (t0 + t1) / 2
        s += "<line id=\"playhead\" x1=\"\(X(initial))\" x2=\"\(X(initial))\" y1=\"4\" y2=\"152\" stroke=\"#e00\" stroke-width=\"2\"/></svg>\n"
        s += "<p class=\"legend\"><span><i style=\"display:inline-block;width:18px;height:8px;background:#f0a030\"></i> tracking limited</span>"
        s += "<span><i style=\"display:inline-block;width:18px;height:8px;background:#802020\"></i> tracking lost</span>"
        s += "<span><i style=\"display:inline-block;width:3px;height:10px;background:#000\"></i> announcement (number)</span>"
        s += "<span><i style=\"display:inline-block;width:3px;height:10px;background:#f07000\"></i> tracking prompt</span>"
        s += "<span><i style=\"display:inline-block;width:8px;height:8px;border-radius:4px;background:#8040c0\"></i> haptic</span>"
        s += "<span><i style=\"display:inline-block;width:8px;height:8px;background:#d22\"></i> wrong way / off route</span>"
        s += "<span><i style=\"display:inline-block;width:8px;height:8px;background:#20a0a0\"></i> re-route</span>"
        s += "<span><i style=\"display:inline-block;width:3px;height:10px;background:#e00\"></i> playhead</span></p>\n"
        return s
    }

    static func announcementTable(result: ReplayResult, track: TruthTrack) -> String {
        var rows: [(t: Double, number: String, kind: String, text: String)] = result.announcements.enumerated().map {
            ($1.t, "\($0 + 1)", "guidance", $1.text)
        }
        rows += result.trackingPrompts.map { ($0.t, "-", "tracking prompt", $0.text) }
        rows.sort { $0.t < $1.t }
        var s = "<h2>Announcements</h2><table><thead><tr><th>#</th><th>time</th><th>from</th><th>said</th><th>true position</th></tr></thead><tbody>"
        for row in rows {
            let pos: String
            if track.isEmpty { pos = "-" } else { let t = track.state(at: row.t); pos = String(format: "(%.1f, %.1f) floor %@", t.x, t.y, t.floorId) }
            s += "<tr><td>\(row.number)</td><td>\(String(format: "%.1f s", row.t))</td><td>\(row.kind)</td><td>\(escape(row.text))</td><td>\(escape(pos))</td></tr>"
        }
        s += "</tbody></table>\n"
        return s
    }
}
