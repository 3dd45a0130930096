import Foundation

// Consistency rules of map format v1 beyond JSON types (docs/map-format.md, "Validation rules").
// MapLoader runs them on every file; importers and generators run them on the buildings they make.

/// Checks a `Building` against the rules of map format v1 and throws the first violation as a `MapError`
/// whose JSON path is where the offending value is (or would be) in the file.
public enum MapValidator {
    /// A sign must be within this distance of some wall segment, meters.
    public static let maximumSignDistanceFromWallMeters = 0.3
    /// A projecting (flag or ceiling-hung) sign must be within this distance of some wall segment, meters.
    public static let maximumProjectingSignDistanceFromWallMeters = 1.5
    /// Walls shorter than this are degenerate, meters.
    public static let minimumWallLengthMeters = 0.001
    /// A sign's facing must have length 1 within this tolerance.
    public static let unitVectorTolerance = 0.01
    /// Largest accepted |coordinate|, meters (a building is far smaller; larger values are unit mistakes).
    public static let maximumCoordinateMeters = 100_000.0
    /// Largest accepted |floor elevation|, meters.
    public static let maximumElevationMeters = 1_000.0
    /// Largest accepted sign width or height, meters.
    public static let maximumSignSizeMeters = 5.0
    /// Largest accepted mounting height, meters.
    public static let maximumMountingHeightMeters = 30.0
    /// Largest accepted door width, meters.
    public static let maximumDoorWidthMeters = 30.0
    /// Largest accepted east-west or north-south extent of one floor, meters: the bounding box of its walls,
    /// doors, signs, points of interest and graph nodes. The localizer core refuses larger floors with the
    /// same limit (LocalizerCore/src/map/localizer_map.cpp, `kMaxFloorExtentM`); checking it here first
    /// means a map that validates also builds.
    public static let maximumFloorExtentMeters = 100_000.0
    /// Most floors a building may have (the localizer core stores floor indices as 16-bit integers).
    public static let maximumFloorCount = 32_767
    /// Most distinct sign kinds a building may have (the localizer core's limit on kind ids).
    public static let maximumSignKindCount = 4_096
    /// Longest sign text (an identifying legend such as a room number), characters.
    public static let maximumSignTextLength = 40
    /// Longest accepted identifier (building, floor, door, sign, point of interest, node), in characters.
    public static let maximumIdentifierLength = 64
    /// The characters an identifier may use: ASCII letters, digits and `.` `_` `:` `-` (docs/map-format.md,
    /// "Identifiers"). Ids end up in HTML attributes, file names, logs and spoken text; a closed set means no
    /// quote, bracket, space or control character ever reaches one of those contexts from a map.
    public static let identifierCharacterSetDescription = "A-Z a-z 0-9 . _ : -"
    /// A point of interest must be at least this far from every wall, meters: the localizer's walkable ground
    /// keeps this clearance (wf_localizer_options.wall_clearance_m, default 0.2 m), so a destination closer to a
    /// wall (or inside one) is a place no estimate can reach and the traveler is never told "Arrived".
    public static let minimumPointOfInterestWallClearanceMeters = 0.2

    /// Throws the first rule `building` breaks; `file` is used in the error only.
    /// - Throws: `MapError`.
    public static func validate(_ building: Building, file: String = "<memory>") throws {
        do { try check(building) } catch let e as PathError { throw e.mapError(file: file) }
    }

    private static func fail(_ path: String, _ reason: String) -> PathError { PathError(path: path, reason: reason) }

    /// A point for an error message, `[x, y]` with `fmt` numbers.
    static func fmt(_ p: Point2) -> String { "[\(fmt(p.x)), \(fmt(p.y))]" }

    /// A number for an error message: rounded to 1 mm (0.001) and written without a fraction when whole;
    /// magnitudes of 10^15 and more (and non-finite values) in Swift's shortest form, e.g. `1e+19`. Never traps
    /// (an `Int` conversion of a double beyond 2^63 would).
    static func fmt(_ v: Double) -> String {
        guard v.isFinite, abs(v) < 1e15 else { return "\(v)" }
        let r = (v * 1000).rounded() / 1000
        if r == r.rounded(), let whole = Int64(exactly: r) { return String(whole) }
        return String(r)
    }

    /// True for the characters `identifierCharacterSetDescription` lists.
    static func isIdentifierCharacter(_ u: Unicode.Scalar) -> Bool {
        switch u.value {
        case 0x30...0x39, 0x41...0x5A, 0x61...0x7A: return true            // 0-9 A-Z a-z
        case 0x2E, 0x5F, 0x3A, 0x2D: return true                             // . _ : -
        default: return false
        }
    }

    /// Checks one identifier: non-empty, at most `maximumIdentifierLength` characters, only the documented
    /// characters. The message names the first offending character by code point (never echoes the raw id,
    /// which may hold control characters).
    private static func checkId(_ s: String, _ path: String) throws {
        if s.trimmingCharacters(in: .whitespacesAndNewlines).isEmpty { throw fail(path, "identifier must not be empty") }
        let scalars = Array(s.unicodeScalars)
        if scalars.count > maximumIdentifierLength {
            throw fail(path, "identifier is \(scalars.count) characters long; at most \(maximumIdentifierLength) are allowed")
        }
        if let i = scalars.firstIndex(where: { !isIdentifierCharacter($0) }) {
            let u = scalars[i]
            let hex = String(u.value, radix: 16, uppercase: true)
            let code = "U+" + String(repeating: "0", count: max(0, 4 - hex.count)) + hex
            let shown = u.value >= 0x21 && u.value < 0x7F ? " (\(Character(u)))" : ""
            throw fail(path, "identifier contains the character \(code)\(shown) at position \(i + 1); identifiers may use only \(identifierCharacterSetDescription)")
        }
    }

    private static func checkNumber(_ v: Double, _ path: String, range: ClosedRange<Double>, what: String) throws {
        guard v.isFinite else { throw fail(path, "\(what) must be a finite number, got \(v)") }
        guard range.contains(v) else {
            throw fail(path, "\(what) \(fmt(v)) is out of range [\(fmt(range.lowerBound)), \(fmt(range.upperBound))]")
        }
    }

    private static func checkPoint(_ p: Point2, _ path: String) throws {
        let m = maximumCoordinateMeters
        try checkNumber(p.x, path + "[0]", range: -m...m, what: "coordinate x (meters)")
        try checkNumber(p.y, path + "[1]", range: -m...m, what: "coordinate y (meters)")
    }

    /// Largest difference, meters, between a sign's face size and its kind's size in "signKinds": 1 mm.
    public static let signSizeToleranceMeters = 0.001

    /// Checks the optional "signKinds" catalogue: at least one entry, kinds non-empty and unique, sizes positive,
    /// finite and at most `maximumSignSizeMeters`. Returns the entries by kind (nil when the map has none).
    private static func checkSignKinds(_ kinds: [SignKindSpec]?) throws -> [String: SignKindSpec]? {
        guard let kinds else { return nil }
        guard !kinds.isEmpty else {
            throw fail("$.signKinds", "signKinds is empty: list each sign kind with its face size, or leave the field out for the defaults")
        }
        var byKind: [String: (spec: SignKindSpec, index: Int)] = [:]
        for (i, k) in kinds.enumerated() {
            let kp = "$.signKinds[\(i)]"
            if k.kind.isEmpty { throw fail(kp + ".kind", "sign kind must not be empty (e.g. \"exit\")") }
            if let first = byKind[k.kind] {
                throw fail(kp + ".kind", "sign kind \"\(k.kind)\" is listed twice (also $.signKinds[\(first.index)]): one size per kind")
            }
            for (key, v) in [("widthMeters", k.widthMeters), ("heightMeters", k.heightMeters)] {
                guard v.isFinite, v > 0, v <= maximumSignSizeMeters else {
                    throw fail("\(kp).\(key)", "sign face size must be in (0, \(fmt(maximumSignSizeMeters))] m, got \(fmt(v))")
                }
            }
            if let r = k.maxRangeMeters {
                try checkNumber(r, kp + ".maxRangeMeters", range: 0.1...100, what: "recognition range (meters)")
            }
            if let a = k.maxViewAngleDeg {
                try checkNumber(a, kp + ".maxViewAngleDeg", range: 1...90, what: "recognition view angle (degrees)")
            }
            if let m = k.mountingHeightMeters {
                try checkNumber(m, kp + ".mountingHeightMeters", range: 0...10, what: "mounting height of the face's bottom edge (meters)")
            }
            byKind[k.kind] = (k, i)
        }
        guard byKind.count <= maximumSignKindCount else {
            throw fail("$.signKinds", "the building has more than \(maximumSignKindCount) distinct sign kinds")
        }
        return byKind.mapValues(\.spec)
    }

    private static func check(_ b: Building) throws {
        guard b.formatVersion == MapLoader.supportedFormatVersion else {
            throw fail("$.formatVersion", "unsupported formatVersion \(b.formatVersion); this build reads version \(MapLoader.supportedFormatVersion)")
        }
        try checkId(b.id, "$.id")
        guard !b.floors.isEmpty else { throw fail("$.floors", "the building has no floors (empty building)") }
        guard b.floors.count <= maximumFloorCount else {
            throw fail("$.floors", "the building has \(b.floors.count) floors; at most \(maximumFloorCount) are supported")
        }
        var signKinds = Set<String>()
        let catalogue = try checkSignKinds(b.signKinds)

        var floorIndex: [String: Int] = [:]
        var poiLocation: [String: (floor: Int, index: Int)] = [:]
        for (fi, f) in b.floors.enumerated() {
            let fp = "$.floors[\(fi)]"
            try checkId(f.id, fp + ".id")
            if let first = floorIndex[f.id] {
                throw fail(fp + ".id", "duplicate floor id \"\(f.id)\" (also $.floors[\(first)])")
            }
            floorIndex[f.id] = fi
            try checkNumber(f.elevationMeters, fp + ".elevationMeters", range: -maximumElevationMeters...maximumElevationMeters,
                            what: "elevation (meters)")
            guard !f.walls.isEmpty else {
                throw fail(fp + ".walls", "floor \"\(f.id)\" has no walls (a zero-area map cannot localize anyone)")
            }
            for (wi, w) in f.walls.enumerated() {
                let wp = "\(fp).walls[\(wi)]"
                try checkPoint(w.from, wp + ".from")
                try checkPoint(w.to, wp + ".to")
                if w.lengthMeters < minimumWallLengthMeters {
                    throw fail(wp, "degenerate wall: its ends coincide (length \(fmt(w.lengthMeters)) m < \(minimumWallLengthMeters) m)")
                }
            }
            var doorIds: [String: Int] = [:]
            for (di, d) in f.doors.enumerated() {
                let dp = "\(fp).doors[\(di)]"
                try checkId(d.id, dp + ".id")
                if let first = doorIds[d.id] { throw fail(dp + ".id", "duplicate door id \"\(d.id)\" on floor \"\(f.id)\" (also \(fp).doors[\(first)])") }
                doorIds[d.id] = di
                try checkPoint(d.position, dp + ".position")
                guard d.widthMeters.isFinite, d.widthMeters > 0 else {
                    throw fail(dp + ".widthMeters", "door width must be a positive number of meters, got \(fmt(d.widthMeters))")
                }
                try checkNumber(d.widthMeters, dp + ".widthMeters", range: 0...maximumDoorWidthMeters, what: "door width (meters)")
            }
            var signIds: [String: Int] = [:]
            var signTexts: [String: Int] = [:]   // kind NUL text -> sign index
            for (si, s) in f.signs.enumerated() {
                let sp = "\(fp).signs[\(si)]"
                try checkId(s.id, sp + ".id")
                if let first = signIds[s.id] { throw fail(sp + ".id", "duplicate sign id \"\(s.id)\" on floor \"\(f.id)\" (also \(fp).signs[\(first)])") }
                signIds[s.id] = si
                if s.kind.isEmpty { throw fail(sp + ".kind", "sign kind must not be empty (e.g. \"exit\")") }
                if signKinds.insert(s.kind).inserted, signKinds.count > maximumSignKindCount {
                    throw fail(sp + ".kind", "the building has more than \(maximumSignKindCount) distinct sign kinds")
                }
                try checkPoint(s.position, sp + ".position")
                try checkPoint(s.facing, sp + ".facing")
                let len = s.facing.vectorLength
                if len == 0 { throw fail(sp + ".facing", "facing is the zero vector; it must be a unit normal pointing away from the wall") }
                if abs(len - 1) > unitVectorTolerance {
                    throw fail(sp + ".facing", "facing must be a unit vector, its length is \(fmt(len))")
                }
                for (key, v) in [("widthMeters", s.widthMeters), ("heightMeters", s.heightMeters)] {
                    guard v.isFinite, v > 0 else { throw fail("\(sp).\(key)", "sign size must be positive, got \(fmt(v)) m") }
                    guard v <= maximumSignSizeMeters else {
                        throw fail("\(sp).\(key)", "sign size \(fmt(v)) m is out of range (0, \(fmt(maximumSignSizeMeters))] m")
                    }
                }
                if let catalogue {
                    guard let spec = catalogue[s.kind] else {
                        throw fail(sp + ".kind", "sign kind \"\(s.kind)\" is not in $.signKinds (kinds: \(catalogue.keys.sorted().joined(separator: ", ")))")
                    }
                    if abs(spec.heightMeters - s.heightMeters) > signSizeToleranceMeters
                        || abs(spec.widthMeters - s.widthMeters) > signSizeToleranceMeters {
                        throw fail(sp, "sign \"\(s.id)\" is \(fmt(s.widthMeters)) x \(fmt(s.heightMeters)) m but $.signKinds gives kind \"\(s.kind)\" \(fmt(spec.widthMeters)) x \(fmt(spec.heightMeters)) m (contradictory sizes)")
                    }
                }
                if let text = s.text {
                    let trimmed = text.trimmingCharacters(in: .whitespacesAndNewlines)
                    guard !trimmed.isEmpty, trimmed == text, text.count <= maximumSignTextLength else {
                        throw fail(sp + ".text", "sign text must be 1 to \(maximumSignTextLength) characters without surrounding spaces (the legend as read, e.g. \"402\"), got \"\(text)\"")
                    }
                    if let first = signTexts[s.kind + "\u{0}" + text] {
                        throw fail(sp + ".text", "sign text \"\(text)\" of kind \"\(s.kind)\" is also on \(fp).signs[\(first)]: a legend that identifies a sign must be unique on its floor")
                    }
                    signTexts[s.kind + "\u{0}" + text] = si
                }
                if let h = s.mountingHeightMeters {
                    try checkNumber(h, sp + ".mountingHeightMeters", range: 0...maximumMountingHeightMeters, what: "mounting height (meters)")
                }
                if let a = s.positionAdjustmentMeters {
                    try checkNumber(a, sp + ".positionAdjustmentMeters", range: 0...maximumCoordinateMeters, what: "position adjustment (meters)")
                }
                let nearest = f.nearestWall(to: s.position)?.distanceMeters ?? .infinity
                switch s.placement {
                case .wall where nearest > maximumSignDistanceFromWallMeters:
                    throw fail(sp + ".position", "sign \"\(s.id)\" is not on a wall: the nearest wall is \(fmt(nearest)) m away (at most \(maximumSignDistanceFromWallMeters) m allowed for a wall sign)")
                case .projecting where nearest > maximumProjectingSignDistanceFromWallMeters:
                    throw fail(sp + ".position", "projecting sign \"\(s.id)\" is not near a wall: the nearest wall is \(fmt(nearest)) m away (at most \(maximumProjectingSignDistanceFromWallMeters) m allowed)")
                default:
                    break
                }
            }
            for (pi, p) in f.pointsOfInterest.enumerated() {
                let pp = "\(fp).pointsOfInterest[\(pi)]"
                try checkId(p.id, pp + ".id")
                if let first = poiLocation[p.id] {
                    throw fail(pp + ".id", "duplicate point-of-interest id \"\(p.id)\" (also $.floors[\(first.floor)].pointsOfInterest[\(first.index)])")
                }
                poiLocation[p.id] = (fi, pi)
                if p.name.trimmingCharacters(in: .whitespaces).isEmpty { throw fail(pp + ".name", "point of interest \"\(p.id)\" has an empty name") }
                if p.category.isEmpty { throw fail(pp + ".category", "point of interest \"\(p.id)\" has an empty category") }
                try checkPoint(p.position, pp + ".position")
            }
        }

        // Graph nodes.
        let g = b.graph
        guard !g.nodes.isEmpty else { throw fail("$.graph.nodes", "the navigation graph has no nodes") }
        var nodeIndex: [String: Int] = [:]
        var poisWithNode = Set<String>()
        for (ni, n) in g.nodes.enumerated() {
            let np = "$.graph.nodes[\(ni)]"
            try checkId(n.id, np + ".id")
            if let first = nodeIndex[n.id] { throw fail(np + ".id", "duplicate node id \"\(n.id)\" (also $.graph.nodes[\(first)])") }
            nodeIndex[n.id] = ni
            guard floorIndex[n.floorId] != nil else {
                throw fail(np + ".floorId", "node \"\(n.id)\" is on unknown floor \"\(n.floorId)\" (floors: \(b.floors.map(\.id).joined(separator: ", ")))")
            }
            try checkPoint(n.position, np + ".position")
            switch n.kind {
            case .pointOfInterest:
                guard let pid = n.pointOfInterestId else {
                    throw fail(np + ".pointOfInterestId", "pointOfInterest node \"\(n.id)\" must name its point of interest")
                }
                guard let loc = poiLocation[pid] else {
                    throw fail(np + ".pointOfInterestId", "node \"\(n.id)\" refers to unknown point of interest \"\(pid)\"")
                }
                if b.floors[loc.floor].id != n.floorId {
                    throw fail(np + ".floorId", "node \"\(n.id)\" is on floor \"\(n.floorId)\" but its point of interest \"\(pid)\" is on floor \"\(b.floors[loc.floor].id)\"")
                }
                poisWithNode.insert(pid)
            case .verticalLink:
                if n.verticalLink == nil {
                    throw fail(np + ".verticalLink", "verticalLink node \"\(n.id)\" must say \"elevator\" or \"stairs\"")
                }
            case .control:
                break
            }
            if n.kind != .pointOfInterest, n.pointOfInterestId != nil {
                throw fail(np + ".pointOfInterestId", "only pointOfInterest nodes may name a point of interest (node \"\(n.id)\" is \(n.kind.rawValue))")
            }
            if n.kind != .verticalLink, n.verticalLink != nil {
                throw fail(np + ".verticalLink", "only verticalLink nodes may have 'verticalLink' (node \"\(n.id)\" is \(n.kind.rawValue))")
            }
        }

        // Edges.
        var seenEdges: [String: Int] = [:]
        var adjacency = Array(repeating: [Int](), count: g.nodes.count)
        var hasCounterpart = Array(repeating: false, count: g.nodes.count)
        for (ei, e) in g.edges.enumerated() {
            let ep = "$.graph.edges[\(ei)]"
            guard let a = nodeIndex[e.from] else { throw fail(ep + ".from", "edge refers to unknown node \"\(e.from)\" (dangling edge)") }
            guard let c = nodeIndex[e.to] else { throw fail(ep + ".to", "edge refers to unknown node \"\(e.to)\" (dangling edge)") }
            if a == c { throw fail(ep, "self-loop: edge joins node \"\(e.from)\" to itself") }
            let key = a < c ? "\(a)-\(c)" : "\(c)-\(a)"
            if let first = seenEdges[key] {
                throw fail(ep, "duplicate edge between \"\(e.from)\" and \"\(e.to)\" (also $.graph.edges[\(first)]; edges are undirected)")
            }
            seenEdges[key] = ei
            let na = g.nodes[a], nc = g.nodes[c]
            if na.floorId != nc.floorId {
                guard na.kind == .verticalLink, nc.kind == .verticalLink else {
                    throw fail(ep, "edge between floors \"\(na.floorId)\" and \"\(nc.floorId)\" must join two verticalLink nodes (\"\(na.id)\" is \(na.kind.rawValue), \"\(nc.id)\" is \(nc.kind.rawValue))")
                }
                guard na.verticalLink == nc.verticalLink else {
                    throw fail(ep, "vertical edge joins \(na.verticalLink!.rawValue) node \"\(na.id)\" to \(nc.verticalLink!.rawValue) node \"\(nc.id)\"")
                }
                let ea = b.floors[floorIndex[na.floorId]!].elevationMeters, ec = b.floors[floorIndex[nc.floorId]!].elevationMeters
                if ea == ec { throw fail(ep, "vertical edge joins floors \"\(na.floorId)\" and \"\(nc.floorId)\" of equal elevation (zero length)") }
                hasCounterpart[a] = true; hasCounterpart[c] = true
            } else {
                let fi = floorIndex[na.floorId]!
                if let wi = b.floors[fi].firstWallCrossed(from: na.position, to: nc.position) {
                    let w = b.floors[fi].walls[wi]
                    throw fail(ep, "edge from \"\(na.id)\" to \"\(nc.id)\" crosses or touches the wall $.floors[\(fi)].walls[\(wi)] (from \(fmt(w.from)) to \(fmt(w.to))): an edge must be walkable in a straight line (open a door gap in the wall or route the edge around it)")
                }
            }
            adjacency[a].append(c); adjacency[c].append(a)
        }

        // Coverage: every point of interest has a node; every vertical link a counterpart on another floor.
        for (fi, f) in b.floors.enumerated() {
            for (pi, p) in f.pointsOfInterest.enumerated() where !poisWithNode.contains(p.id) {
                throw fail("$.floors[\(fi)].pointsOfInterest[\(pi)]", "point of interest \"\(p.id)\" has no graph node (add a pointOfInterest node naming it)")
            }
        }
        for (ni, n) in g.nodes.enumerated() where n.kind == .verticalLink && !hasCounterpart[ni] {
            throw fail("$.graph.nodes[\(ni)]", "verticalLink node \"\(n.id)\" has no counterpart: no edge joins it to a verticalLink node on another floor")
        }

        // Points of interest on walkable ground: clear of walls, and reachable in a straight line from their node.
        var poiNode: [String: GraphNode] = [:]
        for n in g.nodes where n.kind == .pointOfInterest { if let pid = n.pointOfInterestId, poiNode[pid] == nil { poiNode[pid] = n } }
        for (fi, f) in b.floors.enumerated() {
            for (pi, p) in f.pointsOfInterest.enumerated() {
                let pp = "$.floors[\(fi)].pointsOfInterest[\(pi)]"
                guard let node = poiNode[p.id] else { continue }   // coverage above guarantees one
                if let (wi, d) = f.nearestWall(to: p.position), d < minimumPointOfInterestWallClearanceMeters {
                    throw fail(pp + ".position", "point of interest \"\(p.id)\" is inside or against a wall: the wall $.floors[\(fi)].walls[\(wi)] is \(fmt(d)) m away (at least \(minimumPointOfInterestWallClearanceMeters) m needed, so that it lies on walkable ground a traveler can reach)")
                }
                if let wi = f.firstWallCrossed(from: node.position, to: p.position) {
                    throw fail(pp + ".position", "point of interest \"\(p.id)\" cannot be reached from its graph node \"\(node.id)\": the straight line between them crosses the wall $.floors[\(fi)].walls[\(wi)] (it lies inside a wall or on the far side of one)")
                }
            }
        }

        // Floor extents (what the localizer core builds its grids over).
        for (fi, f) in b.floors.enumerated() {
            let nodePoints = g.nodes.lazy.filter { $0.floorId == f.id }.map(\.position)
            let fb = f.bounds
            let r = Rect2(enclosing: [Point2(fb.minX, fb.minY), Point2(fb.maxX, fb.maxY)] + nodePoints)!
            if r.width > maximumFloorExtentMeters || r.height > maximumFloorExtentMeters {
                throw fail("$.floors[\(fi)]", "floor \"\(f.id)\" spans \(fmt(r.width)) m x \(fmt(r.height)) m (x from \(fmt(r.minX)) to \(fmt(r.maxX)), y from \(fmt(r.minY)) to \(fmt(r.maxY)), over its walls, doors, signs, points of interest and graph nodes); at most \(fmt(maximumFloorExtentMeters)) m (100 km) either way is allowed: a larger floor is a unit mistake, and the localizer refuses it")
            }
        }

        // Connectivity over the whole building (vertical edges included).
        var reached = Array(repeating: false, count: g.nodes.count)
        var stack = [0]
        reached[0] = true
        while let i = stack.popLast() {
            for j in adjacency[i] where !reached[j] { reached[j] = true; stack.append(j) }
        }
        if let ni = reached.firstIndex(of: false) {
            let missing = reached.filter { !$0 }.count
            throw fail("$.graph.nodes[\(ni)]", "the navigation graph is disconnected: node \"\(g.nodes[ni].id)\" cannot be reached from \"\(g.nodes[0].id)\" (\(missing) of \(g.nodes.count) nodes unreachable)")
        }
    }
}
