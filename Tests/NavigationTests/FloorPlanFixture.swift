// ASCII floor plans for navigation tests, in the style of OSRM's `features/guidance/*.feature`: a small
// map drawn in characters, a grid size in meters, and a table of expected instructions.
//
// Map characters (one character = one grid cell; row 0 is the top, x grows right = east, y up = north):
//   a-z      graph node (control point, or a point of interest when `pointOfInterest` names it); id = letter
//   E, L     elevator landing; S, T stairs landing. Id = letter + floor id ("E1"). The same letter on two
//            consecutive floors (in the order the floors are added) is one elevator/staircase: linked.
//   - |      corridor: joins the nodes at its ends (horizontal run of '-', vertical run of '|')
//   D        a door on a corridor run (the edge gets `throughDoor`, the floor gets a Door there)
//   #        wall: each '#' is joined to its '#' neighbours right and below by a wall segment through the
//            cell centres; an isolated '#' is a small cross
//   1-9      a marker (e.g. a point of interest's entrance); neither node nor corridor
//   space .  nothing
// Edges that cannot be drawn (diagonals) are added with `way("bc")`: consecutive letters are joined.
import Foundation
import Maps
@testable import Navigation
import TestRandom

struct FloorPlanFixture {
    struct FloorSpec { var id: String; var name: String; var elevationMeters: Double; var map: String }
    struct POISpec { var node: String; var id: String; var name: String; var category: String; var behindDoor: Bool; var entrance: Character? }

    let gridMeters: Double
    private(set) var floors: [FloorSpec] = []
    private(set) var pois: [POISpec] = []
    private(set) var ways: [(floor: String?, nodes: String)] = []
    private(set) var labels: [String: String] = [:]
    private(set) var doorWays: [String] = []

    /// Starts a fixture whose map characters are `gridMeters` apart.
    init(gridMeters: Double) { self.gridMeters = gridMeters }

    /// Adds a floor drawn as ASCII (see the legend at the top of this file).
    func floor(_ id: String, name: String? = nil, elevationMeters: Double? = nil, map: String) -> Self {
        var c = self
        c.floors.append(FloorSpec(id: id, name: name ?? "Floor \(id)",
                                  elevationMeters: elevationMeters ?? Double(floors.count) * 4.0, map: map))
        return c
    }

    /// Makes node `node` a point of interest. `entrance` is a marker character (1-9) on the same floor
    /// giving the place's entrance position; default: the node's position.
    func pointOfInterest(node: String, id: String, name: String, category: String = "room", behindDoor: Bool = false,
                         entrance: Character? = nil) -> Self {
        var c = self
        c.pois.append(POISpec(node: node, id: id, name: name, category: category, behindDoor: behindDoor, entrance: entrance))
        return c
    }

    /// Joins consecutive letters of `nodes` with edges (for corridors that cannot be drawn).
    func way(_ nodes: String, doors: Bool = false) -> Self {
        var c = self
        c.ways.append((nil, nodes))
        if doors { c.doorWays.append(nodes) }
        return c
    }

    /// Gives node `id` a spoken label.
    func label(_ id: String, _ text: String) -> Self {
        var c = self
        c.labels[id] = text
        return c
    }

    private struct Grid {
        let rows: [[Character]]
        func at(_ r: Int, _ c: Int) -> Character? {
            guard r >= 0, r < rows.count, c >= 0, c < rows[r].count else { return nil }
            return rows[r][c]
        }
    }

    private static func isNode(_ ch: Character) -> Bool { ch.isLowercase || "ELST".contains(ch) }

    /// The building described, with ids as in the legend.
    func build() -> Building {
        var builtFloors: [Floor] = []
        var nodes: [GraphNode] = []
        var edges: [GraphEdge] = []
        var verticalByLetter: [Character: [String]] = [:]
        var markers: [Character: (Point2, String)] = [:]
        var nodeIds = Set<String>()
        for spec in floors {
            let lines = spec.map.split(separator: "\n", omittingEmptySubsequences: false).map { Array($0) }
            let grid = Grid(rows: lines)
            let nRows = lines.count
            func point(_ r: Int, _ c: Int) -> Point2 { Point2(x: Double(c) * gridMeters, y: Double(nRows - 1 - r) * gridMeters) }
            func nodeId(_ ch: Character) -> String { ch.isLowercase ? String(ch) : "\(ch)\(spec.id)" }
            var walls: [Wall] = []
            var doors: [Door] = []
            for r in 0..<nRows {
                for c in 0..<lines[r].count {
                    let ch = lines[r][c]
                    if Self.isNode(ch) {
                        let id = nodeId(ch)
                        precondition(!nodeIds.contains(id), "fixture: node '\(id)' drawn twice")
                        nodeIds.insert(id)
                        var n = GraphNode(id: id, kind: .control, floorId: spec.id, position: point(r, c), label: labels[id])
                        if ch.isUppercase {
                            n.kind = .verticalLink
                            n.verticalLink = "EL".contains(ch) ? .elevator : .stairs
                            verticalByLetter[ch, default: []].append(id)
                        }
                        nodes.append(n)
                        // Corridors to the right and downward.
                        for (dr, dc, corridor) in [(0, 1, Character("-")), (1, 0, Character("|"))] {
                            var rr = r + dr, cc = c + dc, steps = 0, door = false
                            while let x = grid.at(rr, cc), x == corridor || x == "D" {
                                if x == "D" { door = true }
                                rr += dr; cc += dc; steps += 1
                            }
                            if steps > 0, let end = grid.at(rr, cc), Self.isNode(end) {
                                edges.append(GraphEdge(from: id, to: nodeId(end), throughDoor: door))
                            }
                        }
                    } else if ch == "D" {
                        doors.append(Door(id: "door-\(spec.id)-\(r)-\(c)", position: point(r, c), widthMeters: 0.9))
                    } else if ch == "#" {
                        let right = grid.at(r, c + 1) == "#", below = grid.at(r + 1, c) == "#"
                        if right { walls.append(Wall(from: point(r, c), to: point(r, c + 1))) }
                        if below { walls.append(Wall(from: point(r, c), to: point(r + 1, c))) }
                        let isolated = !right && !below && grid.at(r, c - 1) != "#" && grid.at(r - 1, c) != "#"
                        if isolated {
                            let p = point(r, c), h = gridMeters / 2
                            walls.append(Wall(from: Point2(x: p.x - h, y: p.y), to: Point2(x: p.x + h, y: p.y)))
                            walls.append(Wall(from: Point2(x: p.x, y: p.y - h), to: Point2(x: p.x, y: p.y + h)))
                        }
                    } else if ch.isNumber {
                        markers[ch] = (point(r, c), spec.id)
                    }
                }
            }
            builtFloors.append(Floor(id: spec.id, name: spec.name, elevationMeters: spec.elevationMeters, walls: walls, doors: doors))
        }
        for (_, ids) in verticalByLetter where ids.count > 1 {
            for k in 0..<(ids.count - 1) { edges.append(GraphEdge(from: ids[k], to: ids[k + 1])) }
        }
        for w in ways {
            let letters = Array(w.nodes).map(String.init)
            for k in 0..<(letters.count - 1) {
                edges.append(GraphEdge(from: letters[k], to: letters[k + 1], throughDoor: doorWays.contains(w.nodes)))
            }
        }
        for poi in pois {
            guard let ni = nodes.firstIndex(where: { $0.id == poi.node }) else { preconditionFailure("fixture: no node '\(poi.node)'") }
            nodes[ni].kind = .pointOfInterest
            nodes[ni].pointOfInterestId = poi.id
            let position = poi.entrance.flatMap { markers[$0]?.0 } ?? nodes[ni].position
            let fi = builtFloors.firstIndex { $0.id == nodes[ni].floorId }!
            builtFloors[fi].pointsOfInterest.append(
                PointOfInterest(id: poi.id, name: poi.name, category: poi.category, position: position, behindDoor: poi.behindDoor))
        }
        return Building(id: "fixture", name: "Fixture", floors: builtFloors, graph: NavigationGraph(nodes: nodes, edges: edges))
    }
}

/// One step of a simulated walk.
enum WalkStep {
    /// Walk in a straight line to a point of the current floor, facing the direction of travel.
    case walk(to: Point2)
    /// Stand still for a while (heading unchanged).
    case wait(seconds: Double)
    /// Arrive on another floor (after a ride), same x, y.
    case changeFloor(to: String)
    /// Arrive on another floor at a given point (landings need not be above one another).
    case appear(at: Point2, floorId: String)
    /// Face a direction (radians, map frame) without moving.
    case face(headingRad: Double)
}

/// A recorded update of a simulated walk.
struct WalkRecord {
    var input: NavigationInput
    var events: [TimedGuidanceEvent]
    var progressMeters: Double
    var nextTurnDistanceMeters: Double?
}

/// Walks a navigator along a path at a fixed speed and update rate, recording every update.
struct Walker {
    var speedMetersPerSecond = 1.2
    var updatesPerSecond = 10.0
    /// Time of the next update, seconds: `startT + updates / updatesPerSecond` (no accumulated rounding).
    var t: Double { startT + Double(updateCount) / updatesPerSecond }
    let startT: Double
    private var updateCount = 0
    var position: Point2
    var floorId: String
    var headingRad: Double
    var records: [WalkRecord] = []
    /// Localizer noise added to each input (not to the true walk): independent Gaussian errors of this
    /// standard deviation on x and y (meters) and on the heading (radians), from a seeded generator.
    var positionNoiseMeters = 0.0
    var headingNoiseRad = 0.0
    var rng = SplitMix64(seed: 1)

    private mutating func gaussian() -> Double {
        // Box-Muller.
        let u1 = max(rng.unit(), 1e-300), u2 = rng.unit()
        return (-2 * log(u1)).squareRoot() * cos(2 * Double.pi * u2)
    }

    init(start: Point2, floorId: String, headingRad: Double = 0, t: Double = 0) {
        position = start; self.floorId = floorId; self.headingRad = headingRad; startT = t
    }

    private mutating func tick(_ nav: Navigator, localized: Bool = true) {
        var estimate = position, heading = headingRad
        if positionNoiseMeters > 0 {
            estimate = Point2(x: position.x + positionNoiseMeters * gaussian(), y: position.y + positionNoiseMeters * gaussian())
        }
        if headingNoiseRad > 0 { heading += headingNoiseRad * gaussian() }
        let input = NavigationInput(t: t, positionInMap: estimate, floorId: floorId, headingRad: heading,
                                    isLocalized: localized, confidence: 1)
        let events = nav.update(input)
        var nextTurn: Double? = nil
        if let r = nav.currentRoute {
            nextTurn = r.maneuvers.first { $0.kind != .depart && $0.distanceFromStartMeters > nav.progressMeters - 1e-9 }
                .map { $0.distanceFromStartMeters - nav.progressMeters }
        }
        records.append(WalkRecord(input: input, events: events, progressMeters: nav.progressMeters, nextTurnDistanceMeters: nextTurn))
        updateCount += 1
    }

    mutating func run(_ nav: Navigator, _ steps: [WalkStep]) {
        let dt = 1 / updatesPerSecond
        for step in steps {
            switch step {
            case .walk(let target):
                let dx = target.x - position.x, dy = target.y - position.y
                let len = (dx * dx + dy * dy).squareRoot()
                if len < 1e-9 { continue }
                headingRad = atan2(dy, dx)
                let n = Int((len / (speedMetersPerSecond * dt)).rounded(.up))
                let start = position
                for k in 1...n {
                    let f = Double(k) / Double(n)
                    position = Point2(x: start.x + dx * f, y: start.y + dy * f)
                    tick(nav)
                }
            case .wait(let seconds):
                for _ in 0..<Int((seconds * updatesPerSecond).rounded()) { tick(nav) }
            case .changeFloor(let f):
                floorId = f
                tick(nav)
            case .appear(let p, let f):
                position = p
                floorId = f
                tick(nav)
            case .face(let h):
                headingRad = h
                tick(nav)
            }
        }
    }

    /// Updates before localization.
    mutating func unlocalized(_ nav: Navigator, seconds: Double) {
        for _ in 0..<Int((seconds * updatesPerSecond).rounded()) { tick(nav, localized: false) }
    }

    var events: [TimedGuidanceEvent] { records.flatMap(\.events) }
    var spoken: [String] { events.compactMap(\.spokenText) }
    var haptics: [HapticPattern] {
        events.compactMap { if case .haptic(let h) = $0.event { return h } else { return nil } }
    }
}

/// Maneuver kinds of a route as a comma-separated list, e.g. "depart,turnLeft,arrive".
func kindsList(_ maneuvers: [Maneuver]) -> String { maneuvers.map(\.kind.rawValue).joined(separator: ",") }

extension Building {
    /// Position of graph node `id` (test helper; traps on an unknown id).
    func nodePosition(_ id: String) -> Point2 { graph.nodes.first { $0.id == id }!.position }
}
