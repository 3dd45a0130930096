// Generator of the bundled sample building Maps/Buildings/wayfinder-office.json ("Wayfinder Office"), a
// made-up two-storey office of the project's own design. The committed JSON is this generator's output;
// BundledMapsTests fails when they differ and rewrites the file when WAYFINDER_REGENERATE_MAPS=1.
//
// Layout of each floor (meters, x east, y north; building 40 x 24):
//   - a rectangular corridor loop 2 m wide: outer edge [6, 34] x [6, 18], inner edge [8, 32] x [8, 16];
//   - a central north-south corridor x in [19, 21] crossing the core and continuing to the facade
//     (floor 1: main entrance at the south end, rear exit at the north end; floor 2: window lounges);
//   - offices on the outer side (6 m deep), in the core: stairwell A (west), restrooms, elevator,
//     kitchen / copy room, conference room, stairwell B (east).
// The plan is nearly symmetric under a 180 degree rotation about (20, 12): the localizer is tested on
// ambiguity. Exit signs are 0.30 x 0.21 m, bottom edge 2.3 m above the floor, on walls facing corridors.
// Tactile signs (bottom edge 1.35 m up) beside doors: a room-number placard at every office, restroom,
// elevator and stairs pictograms at theirs (SignKindSpec.roomPlacard and the pictogram kinds).

/// Builds the bundled "Wayfinder Office" building. Deterministic: same output on every run.
public enum OfficeBuildingGenerator {
    /// Building id written to the file and to recorded sessions.
    public static let buildingId = "wayfinder-office"
    /// Floor-to-floor height, meters.
    public static let floorHeightMeters = 3.8
    /// Clear width of office doors, meters.
    public static let doorWidthMeters = 0.9
    /// Clear width of the entrance / exit doors and corridor openings, meters.
    public static let wideDoorWidthMeters = 1.8
    /// Exit-sign face width, meters (the catalogue's default Exit sign, SignCatalogue.swift).
    public static let exitSignWidthMeters = SignKindSpec.defaultExit.widthMeters
    /// Exit-sign face height, meters (the catalogue's default Exit sign).
    public static let exitSignHeightMeters = SignKindSpec.defaultExit.heightMeters
    /// Height of an Exit sign's bottom edge above the floor, meters.
    public static let exitSignMountingHeightMeters = 2.3

    /// The office's sign kinds: Exit signs, the restroom, elevator and stairs pictograms beside those doors, and a
    /// room-number placard beside every office door (issue 16 section 3).
    public static let signKinds: [SignKindSpec] = [.defaultExit, .restroomPictogram, .elevatorPictogram, .stairsPictogram,
                                                   .roomPlacard]
    /// Distance along the wall from a door's centre to the centre of the plate beside it (latch side), meters.
    public static let plateOffsetFromDoorMeters = 0.75

    /// The building (validated by the caller; `BundledMapsTests` checks it passes `MapValidator`).
    public static func makeBuilding() -> Building {
        var floors: [Floor] = []
        var nodes: [GraphNode] = []
        var edges: [GraphEdge] = []
        for level in 1...2 {
            let f = FloorBuilder(level: level)
            f.build()
            floors.append(f.floor)
            nodes += f.nodes
            edges += f.edges
        }
        // Vertical links: stairwells A and B and the elevator, floor 1 <-> floor 2.
        for stem in ["stairs-a", "stairs-b", "elevator"] {
            edges.append(GraphEdge(from: "\(stem)-1f-landing", to: "\(stem)-2f-landing", throughDoor: false))
        }
        return Building(id: buildingId, name: "Wayfinder Office", floors: floors, graph: NavigationGraph(nodes: nodes, edges: edges),
                        signKinds: signKinds)
    }
}

/// Accumulates one floor's walls, doors, signs, POIs and graph.
private final class FloorBuilder {
    let level: Int
    var floorId: String { "\(level)" }
    var tag: String { "\(level)f" }
    var walls: [Wall] = []
    var doors: [Door] = []
    var signs: [Sign] = []
    var pois: [PointOfInterest] = []
    var nodes: [GraphNode] = []
    var edges: [GraphEdge] = []
    /// Corridor stations per corridor centre line: points where the graph has a control node.
    var controlIds: [Point2: String] = [:]
    /// Corridor polylines (centre lines) whose stations are chained into edges.
    var corridorStations: [String: [Point2]] = [:]

    init(level: Int) { self.level = level }

    var floor: Floor {
        Floor(id: floorId, name: "Floor \(level)", elevationMeters: Double(level - 1) * OfficeBuildingGenerator.floorHeightMeters,
              walls: walls, doors: doors, signs: signs, pointsOfInterest: pois)
    }

    // MARK: walls

    /// Adds an axis-aligned wall line from `a` to `b` with door gaps centred at `gaps` (distance along the
    /// line from `a`) of the given widths.
    func wallLine(_ a: Point2, _ b: Point2, gaps: [(at: Double, width: Double)] = []) {
        let len = a.distance(to: b)
        let ux = (b.x - a.x) / len, uy = (b.y - a.y) / len
        var cursor = 0.0
        for g in gaps.sorted(by: { $0.at < $1.at }) {
            let s = g.at - g.width / 2, e = g.at + g.width / 2
            if s > cursor + 1e-9 {
                walls.append(Wall(from: Point2(a.x + ux * cursor, a.y + uy * cursor), to: Point2(a.x + ux * s, a.y + uy * s)))
            }
            cursor = e
        }
        if len > cursor + 1e-9 {
            walls.append(Wall(from: Point2(a.x + ux * cursor, a.y + uy * cursor), to: b))
        }
    }

    // MARK: graph

    /// The control node at corridor point `p` (created on first use) and registers it on `corridor`.
    @discardableResult
    func station(_ corridor: String, _ p: Point2) -> String {
        corridorStations[corridor, default: []].append(p)
        if let id = controlIds[p] { return id }
        let id = "\(tag)-cp-\(Self.num(p.x))-\(Self.num(p.y))"
        controlIds[p] = id
        nodes.append(GraphNode(id: id, kind: .control, floorId: floorId, position: p))
        return id
    }

    static func num(_ v: Double) -> String { v == v.rounded() ? String(Int(v)) : String(v) }

    /// Adds a point of interest with its node at `door` (the entrance), joined to corridor station `front`.
    @discardableResult
    func place(_ id: String, _ name: String, _ category: String, door: Point2, front: Point2, corridor: String,
               behindDoor: Bool, doorWidth: Double = OfficeBuildingGenerator.doorWidthMeters) -> String {
        pois.append(PointOfInterest(id: id, name: name, category: category, position: door, behindDoor: behindDoor))
        nodes.append(GraphNode(id: id, kind: .pointOfInterest, floorId: floorId, position: door, label: name, pointOfInterestId: id))
        let c = station(corridor, front)
        edges.append(GraphEdge(from: c, to: id, throughDoor: behindDoor))
        if behindDoor { doors.append(Door(id: "door-\(id)", position: door, widthMeters: doorWidth, label: name)) }
        return id
    }

    func exitSign(_ id: String, at p: Point2, facing: Point2, doubleSided: Bool = false) {
        var sign = Sign(id: "exit-\(tag)-\(id)", kind: "exit", position: p, facing: facing,
                          widthMeters: OfficeBuildingGenerator.exitSignWidthMeters,
                          heightMeters: OfficeBuildingGenerator.exitSignHeightMeters,
                          mountingHeightMeters: OfficeBuildingGenerator.exitSignMountingHeightMeters, doubleSided: doubleSided)
        // A double-sided sign here is a flag sign sticking out of its wall.
        if doubleSided { sign.placement = .projecting }
        signs.append(sign)
    }

    /// A tactile sign of `spec`'s kind beside the door at `door` (on the wall along `along`, facing the corridor
    /// side `facing`), `OfficeBuildingGenerator.plateOffsetFromDoorMeters` along the wall, 1 cm off it.
    func plate(_ spec: SignKindSpec, _ id: String, door: Point2, along: Point2, facing: Point2, text: String? = nil) {
        let o = OfficeBuildingGenerator.plateOffsetFromDoorMeters
        var sign = Sign(id: "\(spec.kind)-\(tag)-\(id)", kind: spec.kind,
                        position: Point2(door.x + o * along.x + 0.01 * facing.x, door.y + o * along.y + 0.01 * facing.y),
                        facing: facing, widthMeters: spec.widthMeters, heightMeters: spec.heightMeters,
                        mountingHeightMeters: spec.mountingHeightMeters)
        sign.text = text
        signs.append(sign)
    }

    // MARK: floor

    func build() {
        let d = OfficeBuildingGenerator.doorWidthMeters
        let wide = OfficeBuildingGenerator.wideDoorWidthMeters
        let ground = level == 1

        // Facade; floor 1 has the main entrance (south) and the rear exit (north) at x = 20.
        wallLine(Point2(0, 0), Point2(40, 0), gaps: ground ? [(20, wide)] : [])
        wallLine(Point2(40, 0), Point2(40, 24))
        wallLine(Point2(40, 24), Point2(0, 24), gaps: ground ? [(20, wide)] : [])
        wallLine(Point2(0, 24), Point2(0, 0))

        // Office band walls along the corridor loop. South band offices span x [0,10] [10,14] [14,19]
        // [21,26] [26,30] [30,40]; the north band mirrors it. Door centres (x):
        let bandDoorsX: [Double] = [8, 12, 16.5, 23.5, 28, 32]
        // y = 6 line, x 0..19 and 21..40 (the central passage x 19..21 is open).
        wallLine(Point2(0, 6), Point2(19, 6), gaps: [(8, d), (12, d), (16.5, d)])
        wallLine(Point2(21, 6), Point2(40, 6), gaps: [(2.5, d), (7, d), (11, d)])
        wallLine(Point2(0, 18), Point2(19, 18), gaps: [(8, d), (12, d), (16.5, d)])
        wallLine(Point2(21, 18), Point2(40, 18), gaps: [(2.5, d), (7, d), (11, d)])
        // West and east bands: offices y [6,10] [10,14] [14,18], doors at y 8, 12, 16.
        wallLine(Point2(6, 6), Point2(6, 18), gaps: [(2, d), (6, d), (10, d)])
        wallLine(Point2(34, 6), Point2(34, 18), gaps: [(2, d), (6, d), (10, d)])
        // Office partitions.
        for x in [10.0, 14, 26, 30] {
            wallLine(Point2(x, 0), Point2(x, 6))
            wallLine(Point2(x, 18), Point2(x, 24))
        }
        for y in [10.0, 14] {
            wallLine(Point2(0, y), Point2(6, y))
            wallLine(Point2(34, y), Point2(40, y))
        }
        // Central passage walls (x = 19 and 21) through the south and north bands.
        wallLine(Point2(19, 0), Point2(19, 6))
        wallLine(Point2(21, 0), Point2(21, 6))
        wallLine(Point2(19, 18), Point2(19, 24))
        wallLine(Point2(21, 18), Point2(21, 24))

        // Core: west half [8,19] x [8,16], east half [21,32] x [8,16].
        wallLine(Point2(8, 8), Point2(19, 8), gaps: [(6, d)])            // women's restroom door at x 14
        wallLine(Point2(8, 16), Point2(19, 16), gaps: [(6, d)])          // men's restroom door at x 14
        wallLine(Point2(8, 8), Point2(8, 16), gaps: [(4, d)])            // stairwell A door at y 12
        wallLine(Point2(19, 8), Point2(19, 16), gaps: [(4, 1.2)])        // elevator door at y 12
        wallLine(Point2(21, 8), Point2(32, 8), gaps: [(3.5, d)])         // kitchen / copy room door at x 24.5
        wallLine(Point2(21, 16), Point2(32, 16), gaps: [(3.5, d)])       // conference room door at x 24.5
        wallLine(Point2(32, 8), Point2(32, 16), gaps: [(4, d)])          // stairwell B door at y 12
        wallLine(Point2(21, 8), Point2(21, 16))
        wallLine(Point2(12, 8), Point2(12, 16))                          // stairwell A | restrooms
        wallLine(Point2(12, 12), Point2(16, 12))                         // women's | men's
        wallLine(Point2(16, 8), Point2(16, 16))                          // restrooms | elevator
        wallLine(Point2(16, 10), Point2(19, 10))                         // closet | elevator shaft
        wallLine(Point2(16, 14), Point2(19, 14))                         // elevator shaft | closet
        wallLine(Point2(28, 8), Point2(28, 16))                          // kitchen, conference | stairwell B
        wallLine(Point2(21, 12), Point2(28, 12))                         // kitchen | conference

        // Corridor stations: loop corners and T-junctions first.
        let south = "south", north = "north", west = "west", east = "east", central = "central"
        for p in [Point2(7, 7), Point2(20, 7), Point2(33, 7)] { station(south, p) }
        for p in [Point2(7, 17), Point2(20, 17), Point2(33, 17)] { station(north, p) }
        for p in [Point2(7, 7), Point2(7, 17)] { station(west, p) }
        for p in [Point2(33, 7), Point2(33, 17)] { station(east, p) }
        for p in [Point2(20, 7), Point2(20, 17)] { station(central, p) }

        // Offices: numbering runs counter-clockwise from the south-west corner: south band (west to
        // east), east band (south to north), north band (east to west), west band (north to south).
        var number = level * 100 + 1
        func office(door: Point2, front: Point2, corridor: String) {
            place("room-\(number)", "Room \(number)", "office", door: door, front: front, corridor: corridor, behindDoor: true)
            // The room-number placard beside the door: on the door's wall, toward +x or +y, facing the corridor.
            let facing = Point2(front.x - door.x, front.y - door.y)
            plate(.roomPlacard, "\(number)", door: door, along: Point2(abs(facing.y), abs(facing.x)), facing: facing, text: "\(number)")
            number += 1
        }
        for x in bandDoorsX { office(door: Point2(x, 6), front: Point2(x, 7), corridor: south) }
        for y in [8.0, 12, 16] { office(door: Point2(34, y), front: Point2(33, y), corridor: east) }
        for x in bandDoorsX.reversed() { office(door: Point2(x, 18), front: Point2(x, 17), corridor: north) }
        for y in [16.0, 12, 8] { office(door: Point2(6, y), front: Point2(7, y), corridor: west) }

        // Core rooms.
        place("restroom-\(tag)-women", "Women's restroom", "restroom", door: Point2(14, 8), front: Point2(14, 7), corridor: south, behindDoor: true)
        place("restroom-\(tag)-men", "Men's restroom", "restroom", door: Point2(14, 16), front: Point2(14, 17), corridor: north, behindDoor: true)
        if ground {
            place("kitchen-\(tag)", "Kitchen", "kitchen", door: Point2(24.5, 8), front: Point2(24.5, 7), corridor: south, behindDoor: true)
            place("conference-\(tag)", "Conference room 1A", "conference", door: Point2(24.5, 16), front: Point2(24.5, 17), corridor: north, behindDoor: true)
        } else {
            place("copy-room-\(tag)", "Copy room", "service", door: Point2(24.5, 8), front: Point2(24.5, 7), corridor: south, behindDoor: true)
            place("conference-\(tag)", "Conference room 2A", "conference", door: Point2(24.5, 16), front: Point2(24.5, 17), corridor: north, behindDoor: true)
        }

        // Elevator lobby in the central corridor; the car behind the elevator door.
        place("elevator-lobby-\(tag)", "Elevator lobby", "elevator", door: Point2(20, 12), front: Point2(20, 7), corridor: central, behindDoor: false)
        // The central corridor runs (20, 7) - lobby - (20, 17); it is not chained like the others.
        edges.append(GraphEdge(from: "elevator-lobby-\(tag)", to: station(central, Point2(20, 17)), throughDoor: false))
        nodes.append(GraphNode(id: "elevator-\(tag)-landing", kind: .verticalLink, floorId: floorId, position: Point2(17.5, 12),
                               label: "Elevator", verticalLink: .elevator))
        edges.append(GraphEdge(from: "elevator-lobby-\(tag)", to: "elevator-\(tag)-landing", throughDoor: true))
        doors.append(Door(id: "door-elevator-\(tag)", position: Point2(19, 12), widthMeters: 1.2, label: "Elevator"))

        // Stairwells: POI at the door, landing inside.
        for (letter, door, front, corridor, landing) in [("a", Point2(8, 12), Point2(7, 12), west, Point2(10, 12)),
                                                         ("b", Point2(32, 12), Point2(33, 12), east, Point2(30, 12))] {
            let id = place("stairs-\(letter)-\(tag)", "Stairwell \(letter.uppercased())", "stairs", door: door, front: front,
                           corridor: corridor, behindDoor: true)
            nodes.append(GraphNode(id: "stairs-\(letter)-\(tag)-landing", kind: .verticalLink, floorId: floorId, position: landing,
                                   label: "Stairwell \(letter.uppercased())", verticalLink: .stairs))
            edges.append(GraphEdge(from: id, to: "stairs-\(letter)-\(tag)-landing", throughDoor: false))
        }

        // Ends of the central passage: exits on floor 1, window lounges on floor 2.
        if ground {
            place("exit-main-entrance", "Main entrance", "exit", door: Point2(20, 0), front: Point2(20, 7), corridor: central,
                  behindDoor: true, doorWidth: wide)
            place("exit-rear", "Rear exit", "exit", door: Point2(20, 24), front: Point2(20, 17), corridor: central,
                  behindDoor: true, doorWidth: wide)
        } else {
            place("lounge-\(tag)-south", "South lounge", "lounge", door: Point2(20, 3), front: Point2(20, 7), corridor: central, behindDoor: false)
            place("lounge-\(tag)-north", "North lounge", "lounge", door: Point2(20, 21), front: Point2(20, 17), corridor: central, behindDoor: false)
        }
        corridorStations[central] = nil // joined through the lobby above, not chained

        // Chain the stations of each straight corridor in order.
        for (name, pts) in corridorStations.sorted(by: { $0.key < $1.key }) {
            let horizontal = name == south || name == north
            let unique = Array(Set(pts)).sorted { horizontal ? $0.x < $1.x : $0.y < $1.y }
            for (a, b) in zip(unique, unique.dropFirst()) {
                edges.append(GraphEdge(from: controlIds[a]!, to: controlIds[b]!, throughDoor: false))
            }
        }

        // Pictograms beside the restroom, elevator and stairwell doors, facing the corridor they open on.
        plate(.restroomPictogram, "women", door: Point2(14, 8), along: Point2(1, 0), facing: Point2(0, -1))
        plate(.restroomPictogram, "men", door: Point2(14, 16), along: Point2(1, 0), facing: Point2(0, 1))
        plate(.elevatorPictogram, "door", door: Point2(19, 12.2), along: Point2(0, 1), facing: Point2(1, 0))
        plate(.stairsPictogram, "a", door: Point2(8, 12), along: Point2(0, -1), facing: Point2(-1, 0))
        plate(.stairsPictogram, "b", door: Point2(32, 12), along: Point2(0, 1), facing: Point2(1, 0))

        // Exit signs: at the four ends of the south and north corridors (seen down the corridor), beside
        // both stairwell doors, on the core walls at the central T-junctions pointing to the exits or
        // stairs, and (floor 1) one double-sided flag sign in the central corridor.
        exitSign("sw", at: Point2(6, 7), facing: Point2(1, 0))
        exitSign("se", at: Point2(34, 7), facing: Point2(-1, 0))
        exitSign("nw", at: Point2(6, 17), facing: Point2(1, 0))
        exitSign("ne", at: Point2(34, 17), facing: Point2(-1, 0))
        exitSign("stairs-a", at: Point2(8, 13.2), facing: Point2(-1, 0))
        exitSign("stairs-b", at: Point2(32, 10.8), facing: Point2(1, 0))
        exitSign("south-t", at: Point2(18.6, 8), facing: Point2(0, -1))
        exitSign("north-t", at: Point2(21.4, 16), facing: Point2(0, 1))
        if ground {
            exitSign("central-flag", at: Point2(19.15, 9), facing: Point2(0, -1), doubleSided: true)
        }
    }
}
