// A route as drawn and followed: the polyline from the snapped start through the graph nodes to the
// destination, distances along it, and its maneuvers.
import Foundation
import Maps

/// One vertex of a route polyline.
public struct RoutePoint: Sendable, Equatable {
    /// Position, meters in the floor's frame.
    public var position: Point2
    /// Floor of the position.
    public var floorId: String
    /// Graph node id; nil for the snapped start point.
    public var nodeId: String?
}

/// A route from a snapped position to the destination.
public struct Route: Sendable, Equatable {
    /// Destination node id.
    public var destinationNodeId: String
    /// Graph node ids visited, in order (the snapped start is not a node).
    public var nodeIds: [String]
    /// Polyline: the snapped start, then one point per node. Consecutive points on different floors are a
    /// ride (elevator or stairs) and have no horizontal length.
    public var points: [RoutePoint]
    /// Horizontal distance along the route to each point, meters (`points.count` values, first 0).
    public var cumulativeMeters: [Double]
    /// Routing cost (meters plus penalties, see `RoutingOptions`).
    public var costMeters: Double
    /// Typed maneuvers, first `depart`, last `arrive`.
    public var maneuvers: [Maneuver]
    /// Graph edge index of each polyline segment (segment i joins points i and i+1).
    public var segmentEdges: [Int]
    /// Whether each segment is a ride between floors.
    var segmentVertical: [Bool]

    /// Horizontal length, meters.
    public var lengthMeters: Double { cumulativeMeters.last ?? 0 }

    /// Distance along the route at continuous polyline position `u` (point index + fraction).
    func distanceAlong(_ u: Double) -> Double {
        guard !points.isEmpty else { return 0 }
        let i = max(0, min(points.count - 1, Int(u.rounded(.down))))
        if i >= points.count - 1 { return cumulativeMeters[points.count - 1] }
        let f = u - Double(i)
        return cumulativeMeters[i] + f * (cumulativeMeters[i + 1] - cumulativeMeters[i])
    }

    /// Point at distance `s` along the route, searching forward from segment `hint`; returns the segment
    /// and the point (on the floor of that segment's start).
    func point(atDistance s: Double, fromSegment hint: Int) -> (segment: Int, point: Vec2) {
        var i = max(0, min(hint, points.count - 2))
        while i < points.count - 2 && cumulativeMeters[i + 1] < s { i += 1 }
        let a = Vec2(points[i].position), b = Vec2(points[i + 1].position)
        let len = cumulativeMeters[i + 1] - cumulativeMeters[i]
        if len <= 1e-9 || segmentVertical[i] { return (i, a) }
        let f = max(0, min(1, (s - cumulativeMeters[i]) / len))
        return (i, a + (b - a) * f)
    }
}

/// Builds routes and their maneuvers from shortest paths.
struct RouteBuilder {
    let graph: RoutingGraph
    /// Two opposite turns closer than this whose net change of direction is straight are one corridor
    /// jog, announced as a single slight turn (OSRM collapses such short segments the same way), meters.
    var jogMaxMeters = 1.5
    /// A door is matched to a door edge when within this distance of the segment, meters.
    var doorMatchMeters = 1.5
    /// A turn, ride or door this close after a turn, ride or landing is announced with it, meters: the
    /// cue is said 0.75 m before its point and lasts up to 1.6 s (4 words at 2.5 words/s), 1.9 m at
    /// 1.2 m/s, so a second cue within about 2.7 m would have to cut it off or come late.
    static let chainMeters = 3.0

    /// - Parameter destinationBehindDoor: when true, a door on the last segment is announced by the
    ///   arrival phrase ("..., behind a door") instead of a separate maneuver.
    func build(path: PathResult, routeCost: Double, destinationBehindDoor: Bool, destinationName: String) -> Route {
        let g = graph
        var points: [RoutePoint] = [RoutePoint(position: path.start.point, floorId: path.start.floorId, nodeId: nil)]
        for v in path.nodeIndices {
            points.append(RoutePoint(position: g.nodes[v].position, floorId: g.nodes[v].floorId, nodeId: g.nodes[v].id))
        }
        let segEdges = path.edgeIndices
        var vertical: [Bool] = []
        var cum: [Double] = [0]
        for i in 0..<(points.count - 1) {
            let v = points[i].floorId != points[i + 1].floorId
            vertical.append(v)
            let len = v ? 0 : Vec2(points[i].position).distance(to: Vec2(points[i + 1].position))
            cum.append(cum[i] + len)
        }
        var route = Route(destinationNodeId: g.nodes[path.nodeIndices.last!].id,
                          nodeIds: path.nodeIndices.map { g.nodes[$0].id }, points: points, cumulativeMeters: cum,
                          costMeters: routeCost, maneuvers: [], segmentEdges: segEdges, segmentVertical: vertical)
        route.maneuvers = maneuvers(for: route, destinationBehindDoor: destinationBehindDoor,
                                    destinationName: destinationName)
        return route
    }

    private func floorName(_ id: String) -> String { graph.building.floor(id: id)?.name ?? id }

    func maneuvers(for route: Route, destinationBehindDoor: Bool, destinationName: String) -> [Maneuver] {
        let pts = route.points
        let n = pts.count
        let vertical = route.segmentVertical
        func segLen(_ i: Int) -> Double { route.cumulativeMeters[i + 1] - route.cumulativeMeters[i] }
        func dir(_ i: Int) -> Vec2 { Vec2(pts[i + 1].position) - Vec2(pts[i].position) }
        let eps = 1e-6
        var list: [Maneuver] = []
        func make(_ kind: ManeuverKind, at u: Double, point: Vec2, floor: String, node: String?) -> Maneuver {
            var m = Maneuver(kind: kind, position: point.point2, floorId: floor, nodeId: node)
            m.polylinePosition = u
            return m
        }
        list.append(make(.depart, at: 0, point: Vec2(pts[0].position), floor: pts[0].floorId, node: pts[0].nodeId))

        var q = 1
        while q < n - 1 {
            let inV = vertical[q - 1], outV = vertical[q]
            if outV && !inV {
                var j = q
                while j < n - 1 && vertical[j] { j += 1 }
                let kind: ManeuverKind = graph.edgeKind[route.segmentEdges[q]] == .stairs ? .takeStairs : .takeElevator
                var m = make(kind, at: Double(q), point: Vec2(pts[q].position), floor: pts[q].floorId, node: pts[q].nodeId)
                m.toFloorId = pts[j].floorId
                m.toFloorName = floorName(pts[j].floorId)
                m.label = graph.nodeIndexById[pts[q].nodeId ?? ""].flatMap { graph.nodes[$0].label }
                list.append(m)
            } else if inV && !outV {
                list.append(make(.continue, at: Double(q), point: Vec2(pts[q].position), floor: pts[q].floorId,
                                 node: pts[q].nodeId))
            } else if !inV && !outV && segLen(q) > eps {
                // Incoming direction: the last segment of non-zero length before q, on this floor.
                var k = q - 1
                while k >= 0 && !vertical[k] && segLen(k) <= eps { k -= 1 }
                if k >= 0 && !vertical[k] {
                    let a = signedTurnAngleRad(from: dir(k), to: dir(q)) * 180 / Double.pi
                    if let kind = TurnClassifier.classify(signedAngleDeg: a) {
                        var m = make(kind, at: Double(q), point: Vec2(pts[q].position), floor: pts[q].floorId,
                                     node: pts[q].nodeId)
                        m.turnAngleDeg = a
                        m.label = graph.nodeIndexById[pts[q].nodeId ?? ""].flatMap { graph.nodes[$0].label }
                        list.append(m)
                    }
                }
            }
            q += 1
        }
        collapseJogs(&list, route: route)

        // Doors: one maneuver per door edge, at the door's projection when a door of the floor lies on the
        // edge, else at the edge's midpoint.
        for i in 0..<(n - 1) where !vertical[i] && graph.edgeDoor[route.segmentEdges[i]] {
            if i == n - 2 && destinationBehindDoor { continue }
            let a = Vec2(pts[i].position), b = Vec2(pts[i + 1].position)
            // The snapped start segment is part of a door edge: skip when the start is already past the door.
            let e = route.segmentEdges[i]
            let ea = graph.positions[graph.edgeFrom[e]], eb = graph.positions[graph.edgeTo[e]]
            var doorPoint = (ea + eb) * 0.5
            var doorLabel: String? = nil
            if let floor = graph.building.floor(id: pts[i].floorId) {
                var best = doorMatchMeters
                for d in floor.doors {
                    let pr = projectOntoSegment(Vec2(d.position), ea, eb)
                    if pr.distance <= best { best = pr.distance; doorPoint = pr.point; doorLabel = d.label }
                }
            }
            let pr = projectOntoSegment(doorPoint, a, b)
            if pr.distance > 1e-6 { continue }  // the door is on the part of the edge behind the start
            var m = make(.goThroughDoor, at: Double(i) + pr.t, point: pr.point, floor: pts[i].floorId, node: nil)
            m.label = doorLabel
            list.append(m)
        }

        var arrive = make(.arrive, at: Double(n - 1), point: Vec2(pts[n - 1].position), floor: pts[n - 1].floorId,
                          node: pts[n - 1].nodeId)
        arrive.label = destinationName
        list.append(arrive)

        // Order along the route; at the same place a turn precedes a door (stable sort keeps build order).
        let order = list.indices.sorted { (list[$0].polylinePosition, $0) < (list[$1].polylinePosition, $1) }
        var sorted = order.map { list[$0] }
        for i in sorted.indices {
            sorted[i].distanceFromStartMeters = route.distanceAlong(sorted[i].polylinePosition)
        }
        for i in sorted.indices {
            sorted[i].distanceToNextMeters = i + 1 < sorted.count
                ? sorted[i + 1].distanceFromStartMeters - sorted[i].distanceFromStartMeters : 0
        }
        // Chaining: only onto a maneuver that has a cue of its own (not itself chained, not a door, whose
        // cue ranks lower and may be dropped), and only a turn, ride or door.
        for j in sorted.indices.dropFirst(2) {
            let i = j - 1
            // Not after a landing: its phrase is long and the traveler just stepped out; what follows
            // gets its own cue (the landing phrase is shortened instead, see `Narrative.cue`).
            let leader = sorted[i].kind.isTurn || sorted[i].kind == .takeElevator || sorted[i].kind == .takeStairs
            let follower = sorted[j].kind.isTurn || sorted[j].kind == .takeElevator || sorted[j].kind == .takeStairs
                || sorted[j].kind == .goThroughDoor
            if leader && follower && !sorted[i].announcedWithPrevious
                && sorted[i].distanceToNextMeters < Self.chainMeters {
                sorted[j].announcedWithPrevious = true
            }
        }
        return sorted
    }

    /// Replaces a pair of opposite turns less than `jogMaxMeters` apart, whose net change of direction is
    /// straight, with one slight turn toward the side of the jog at the first control point. A slight
    /// bend less than `jogMaxMeters` before or after an opposite turn is not a maneuver of its own either:
    /// walking (and cutting) the two corners is one turn by their net angle, at the larger turn's control
    /// point ("Bear right now. Then turn left." for a 25-degree bend right a meter before a 90-degree left,
    /// or "Turn right now. Then bear left." for a 90-degree right with a 27-degree bend left a meter after
    /// it, as SKERI floor 4 draws the corner at node-72, would name a bend nobody walks).
    private func collapseJogs(_ list: inout [Maneuver], route: Route) {
        var i = 1
        while i + 1 < list.count {
            let a = list[i], b = list[i + 1]
            let close = route.distanceAlong(b.polylinePosition) - route.distanceAlong(a.polylinePosition) < jogMaxMeters
            if a.kind.isTurn, b.kind.isTurn, let aa = a.turnAngleDeg, let ba = b.turnAngleDeg, aa * ba < 0, close {
                if abs(aa + ba) < TurnClassifier.straightBelowDeg, abs(aa) < TurnClassifier.turnBelowDeg {
                    var m = a
                    m.kind = aa > 0 ? .slightLeft : .slightRight
                    list[i] = m
                    list.remove(at: i + 1)
                } else if abs(aa) < TurnClassifier.slightBelowDeg || abs(ba) < TurnClassifier.slightBelowDeg,
                          let kind = TurnClassifier.classify(signedAngleDeg: aa + ba) {
                    var m = abs(aa) < abs(ba) ? b : a
                    m.kind = kind
                    m.turnAngleDeg = aa + ba
                    list[i] = m
                    list.remove(at: i + 1)
                }
            }
            i += 1
        }
    }
}
