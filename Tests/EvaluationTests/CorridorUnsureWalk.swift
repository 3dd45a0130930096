import Maps
import SessionFormat
import WayfinderCore

/// A test walk for the guidance while not localized: a corridor x 0...20, y 0...2 closed at both ends; the true
/// walker stands at x 18.5 facing east (the end wall 1.5 m ahead) for 10 s at 10 Hz while the estimate, not
/// localized, puts them at x 10. "unsure" is in force until 4 s, then "ahead", spoken at 4 s (unsafe from the
/// true pose: it walks into the end wall).
enum CorridorUnsureWalk {
    static let building: Building = {
        let walls = [Wall(from: Point2(0, 0), to: Point2(20, 0)), Wall(from: Point2(0, 2), to: Point2(20, 2)),
                     Wall(from: Point2(0, 0), to: Point2(0, 2)), Wall(from: Point2(20, 0), to: Point2(20, 2))]
        return Building(id: "c", name: "Corridor", floors: [Floor(id: "1", name: "F", elevationMeters: 0, walls: walls)],
                        graph: NavigationGraph(nodes: [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(1, 1))],
                                               edges: []))
    }()

    static let truth: [TruthRecord] = stride(from: 0.0, through: 10, by: 0.1).map {
        TruthRecord(t: $0, x: 18.5, y: 1, floorId: "1", headingRad: 0)
    }

    /// The trace (index 40 = 4 s, the spoken "ahead").
    static var trace: [TraceRecord] {
        var trace = truth.map { r in
            TraceRecord(t: r.t, x: 10, y: 1, floorId: "1", headingRad: 0, confidence: 0.2, localized: false, hypotheses: 2,
                        sightings: 0, announcements: [], haptics: [])
        }
        for i in trace.indices { trace[i].advice = trace[i].t < 4 - 1e-9 ? "unsure" : "ahead" }
        trace[40].spokenAdvice = "ahead"
        return trace
    }
}
