import Foundation

/// Why an iNavigate map folder could not be imported: the file and the reason.
public struct InavigateImportError: Error, CustomStringConvertible, Sendable {
    /// Path of the offending (or missing) file.
    public let file: String
    /// What is wrong.
    public let reason: String
    /// Creates an error.
    public init(file: String, reason: String) { self.file = file; self.reason = reason }
    /// `file: reason`.
    public var description: String { "\(file): \(reason)" }
}

/// Converts the maps of the reference iNavigate app (Coughlan-Lab/iNavigate `res/maps/<building>/`; the
/// Smith-Kettlewell copy is in ../shared/data/skeri_inavigate, described by its SOURCE.md) to map format v1.
///
/// - `info.yml`: one `floor:` record per floor (`id`, `walls`, `features_file`, `scale` in pixels/m).
/// - `walls_N.bmp`: wall mask (luma >= 128 = wall) -> wall segments by `WallTracer` (both faces of every
///   wall), pixel lattice (u, v) -> meters x = u / scale, y = (rows - v) / scale.
/// - `mapFeatures_N.yml`: `map_feature` records; `type: exit_sign` -> an `exit` sign at `position` [a, b]
///   (meters from the image's bottom-left corner, x right, y up: the map frame as is), facing `normal`.
///   Each surveyed sign is moved onto the wall face behind it (or the nearest face with free space on its
///   facing side) when one is within `maximumSnapDistanceMeters`; the move is kept in
///   `positionAdjustmentMeters`. Two records at one position with opposite normals stay two one-sided
///   entries but are one double-faced sign hung across the corridor or flag-mounted: like signs with no
///   wall within reach, they are kept where surveyed with placement `.projecting`.
/// - `navgraph.json`: nodes keyed by id, `position` in PIXELS [column, row] of the node's floor image,
///   `type` control / destination / link; `weights` is the dense adjacency matrix (node k = index k - 1,
///   non-zero = edge). Destinations become points of interest (named from their labels, category
///   inferred) behind a door when `isDoor` is 1; edges touching such a destination go through the door.
///   Link nodes with the same label on different floors are joined floor by floor (vertical edges).
public enum InavigateImporter {
    /// Import settings; the defaults are the Smith-Kettlewell survey's values.
    public struct Options: Sendable {
        /// Floor-to-floor height used for elevations (not in the source data): floor N is at (N - 1) x this.
        public var floorHeightMeters = 4.0
        /// Exit-sign face width, meters (not in the source data; a standard US Exit sign: the catalogue's default
        /// Exit sign, SignCatalogue.swift).
        public var signWidthMeters = SignKindSpec.defaultExit.widthMeters
        /// Exit-sign face height, meters (fits the surveyed photos, ../shared/reference/arkit-frames.md; the
        /// catalogue's default Exit sign).
        public var signHeightMeters = SignKindSpec.defaultExit.heightMeters
        /// Mounting height used when a sign record has no `height`, meters.
        public var defaultSignMountingHeightMeters = 2.38
        /// A sign further than this from every wall is left where surveyed (and then fails validation).
        public var maximumSnapDistanceMeters = 0.5
        /// Wall-mask components smaller than this many pixels are dropped as specks.
        public var minimumWallComponentPixels = 3
        /// Creates the default options.
        public init() {}
    }

    /// What the import did, per floor.
    public struct FloorReport: Sendable {
        /// Floor id.
        public let floorId: String
        /// Wall segments traced.
        public let walls: Int
        /// Exit signs imported.
        public let signs: Int
        /// How far each sign was moved onto its wall, meters, in sign order.
        public let signAdjustmentsMeters: [Double]
        /// Points of interest (navgraph destinations).
        public let pointsOfInterest: Int
        /// Graph nodes on this floor.
        public let nodes: Int
    }

    /// Imports the iNavigate map folder at `directory` (the folder holding info.yml, or its parent holding
    /// `floors/info.yml`), validates the result with `MapValidator` and reports per floor.
    /// - Throws: `InavigateImportError` for missing or damaged input files, `MapError` when the converted
    ///   building breaks a format rule.
    public static func importBuilding(from directory: URL, options: Options = Options()) throws -> (building: Building, report: [FloorReport]) {
        var dir = directory
        if !FileManager.default.fileExists(atPath: dir.appendingPathComponent("info.yml").path),
           FileManager.default.fileExists(atPath: dir.appendingPathComponent("floors/info.yml").path) {
            dir = dir.appendingPathComponent("floors")
        }
        let infoURL = dir.appendingPathComponent("info.yml")
        let info = try yaml(infoURL)
        let floorRecords = info.records.filter { $0.key == "floor" }
        guard !floorRecords.isEmpty else { throw InavigateImportError(file: infoURL.path, reason: "no 'floor:' records") }
        let buildingName = info.scalars["building_name"] ?? dir.deletingLastPathComponent().lastPathComponent

        struct FloorSource { let id: String; let number: Int; let scale: Double; let rows: Int; let floor: Floor }
        var sources: [FloorSource] = []
        var reports: [String: (walls: Int, signs: [Double])] = [:]
        var anglesToNorthDeg: [Double] = []
        for rec in floorRecords {
            func field(_ k: String) throws -> String {
                guard let v = rec.fields[k], !v.isEmpty else {
                    throw InavigateImportError(file: infoURL.path, reason: "floor record at line \(rec.line) has no '\(k)'")
                }
                return v
            }
            let id = try field("id")
            guard let number = Int(id) else { throw InavigateImportError(file: infoURL.path, reason: "floor id '\(id)' (line \(rec.line)) is not a floor number") }
            // Floor N is at (N - 1) x floorHeightMeters; a number whose elevation is off the map format's range is
            // refused here (computing N - 1 for Int.min would also overflow).
            let elevation = (Double(number) - 1) * options.floorHeightMeters
            guard abs(elevation) <= MapValidator.maximumElevationMeters else {
                throw InavigateImportError(file: infoURL.path, reason: "floor id '\(id)' (line \(rec.line)): its elevation, (\(id) - 1) x \(options.floorHeightMeters) m, is beyond the \(MapValidator.maximumElevationMeters) m the map format allows")
            }
            guard let scale = Double(try field("scale")), scale.isFinite, scale > 0 else {
                throw InavigateImportError(file: infoURL.path, reason: "floor \(id): scale must be a positive number of pixels per meter")
            }
            if let a = rec.fields["angle_to_north"] {
                guard let deg = Double(a), deg.isFinite else {
                    throw InavigateImportError(file: infoURL.path, reason: "floor \(id): angle_to_north must be a number of degrees")
                }
                anglesToNorthDeg.append(deg)
            }
            if sources.contains(where: { $0.id == id }) { throw InavigateImportError(file: infoURL.path, reason: "floor \(id) is listed twice") }
            let wallsURL = dir.appendingPathComponent(try field("walls"))
            let image: GrayImage
            do { image = try BMPReader.read(contentsOf: wallsURL) } catch let e as BMPError {
                throw InavigateImportError(file: e.file, reason: e.reason)
            }
            let mask = image.pixels.map { $0 >= 128 }
            guard mask.contains(true) else { throw InavigateImportError(file: wallsURL.path, reason: "the wall mask has no wall (white) pixels") }
            let lattice = WallTracer.trace(mask: mask, width: image.width, height: image.height,
                                           minimumComponentPixels: options.minimumWallComponentPixels)
            let rows = Double(image.height)
            func meters(_ p: Point2) -> Point2 { Point2(p.x / scale, (rows - p.y) / scale) }
            let walls = lattice.map { Wall(from: meters($0.from), to: meters($0.to)) }

            // Signs.
            let featuresURL = dir.appendingPathComponent(try field("features_file"))
            let features = try yaml(featuresURL)
            var signs: [Sign] = []
            var adjustments: [Double] = []
            // Positions surveyed twice with opposite normals: one double-faced sign hung across the corridor
            // or flag-mounted; those entries are kept where surveyed (projecting), not pushed onto a wall.
            var surveyedFaces: [String: [[Double]]] = [:]
            for f in features.records where f.key == "map_feature" && f.fields["type"] == "exit_sign" {
                if let pos = f.fields["position"].flatMap(SimpleYAML.numbers), let nrm = f.fields["normal"].flatMap(SimpleYAML.numbers) {
                    surveyedFaces[pos.map { String(format: "%.3f", $0) }.joined(separator: ","), default: []].append(nrm)
                }
            }
            func isBackToBack(_ pos: [Double], _ nrm: [Double]) -> Bool {
                let faces = surveyedFaces[pos.map { String(format: "%.3f", $0) }.joined(separator: ",")] ?? []
                return faces.contains { $0.count == 2 && nrm.count == 2 && $0[0] * nrm[0] + $0[1] * nrm[1] < 0 }
            }
            for f in features.records where f.key == "map_feature" {
                guard let type = f.fields["type"] else {
                    throw InavigateImportError(file: featuresURL.path, reason: "map_feature at line \(f.line) has no 'type'")
                }
                guard type == "exit_sign" else { continue }
                guard let pos = f.fields["position"].flatMap(SimpleYAML.numbers), pos.count == 2 else {
                    throw InavigateImportError(file: featuresURL.path, reason: "map_feature at line \(f.line): 'position' must be [a, b] in meters")
                }
                guard let nrm = f.fields["normal"].flatMap(SimpleYAML.numbers), nrm.count == 2 else {
                    throw InavigateImportError(file: featuresURL.path, reason: "map_feature at line \(f.line): 'normal' must be [x, y]")
                }
                let len = (nrm[0] * nrm[0] + nrm[1] * nrm[1]).squareRoot()
                guard len > 1e-9 else { throw InavigateImportError(file: featuresURL.path, reason: "map_feature at line \(f.line): 'normal' is zero") }
                var mounting = options.defaultSignMountingHeightMeters
                if let h = f.fields["height"] {
                    guard let v = Double(h), v.isFinite, v >= 0 else {
                        throw InavigateImportError(file: featuresURL.path, reason: "map_feature at line \(f.line): 'height' must be a number of meters")
                    }
                    mounting = v
                }
                let featureId = f.fields["id"] ?? String(signs.count)
                let facing = Point2(nrm[0] / len, nrm[1] / len)
                let surveyed = Point2(pos[0], pos[1])
                let snapped = isBackToBack(pos, nrm) ? nil
                    : snap(surveyed, facing: facing, walls: walls, mask: mask, width: image.width, height: image.height,
                           scale: scale, maximumMeters: options.maximumSnapDistanceMeters)
                let moved = snapped.map { surveyed.distance(to: $0) } ?? 0
                adjustments.append(moved)
                var sign = Sign(id: "exit-\(id)-\(featureId)", kind: "exit", position: snapped ?? surveyed, facing: facing,
                                widthMeters: options.signWidthMeters, heightMeters: options.signHeightMeters,
                                mountingHeightMeters: mounting, doubleSided: false)
                sign.positionAdjustmentMeters = (moved * 1e6).rounded() / 1e6
                // Back-to-back pair, or no wall face within reach: a flag or ceiling-hung sign, kept where surveyed.
                if snapped == nil { sign.placement = .projecting }
                signs.append(sign)
            }
            if let dup = Dictionary(grouping: signs, by: \.id).first(where: { $0.value.count > 1 }) {
                throw InavigateImportError(file: featuresURL.path, reason: "two map_feature records have id \(dup.key.split(separator: "-").last ?? "")")
            }
            reports[id] = (walls.count, adjustments)
            let floor = Floor(id: id, name: "Floor \(id)", elevationMeters: elevation,
                              walls: walls, doors: [], signs: signs, pointsOfInterest: [])
            sources.append(FloorSource(id: id, number: number, scale: scale, rows: image.height, floor: floor))
        }
        sources.sort { $0.number < $1.number }

        // Navigation graph.
        let graphURL = dir.appendingPathComponent("navgraph.json")
        let root: JSONValue
        do {
            guard let data = try? Data(contentsOf: graphURL) else { throw InavigateImportError(file: graphURL.path, reason: "no such file or unreadable") }
            root = try JSONParser.parse([UInt8](data))
        } catch let e as JSONSyntaxError {
            throw InavigateImportError(file: graphURL.path, reason: "not valid JSON: \(e.description)")
        }
        func bad(_ r: String) -> InavigateImportError { InavigateImportError(file: graphURL.path, reason: r) }
        guard case .object(let top) = root else { throw bad("expected a JSON object") }
        let topDict = Dictionary(top.map { ($0.key, $0.value) }, uniquingKeysWith: { a, _ in a })
        guard case .object(let nodeMembers)? = topDict["nodes"] else { throw bad("missing object 'nodes'") }
        guard case .array(let weightRows)? = topDict["weights"] else { throw bad("missing array 'weights'") }

        struct RawNode { let number: Int; let type: String; let col: Double; let row: Double; let floor: String; let label: String; let isDoor: Bool }
        var raw: [RawNode] = []
        for (key, value) in nodeMembers {
            guard case .object(let m) = value else { throw bad("node \(key) is not an object") }
            let d = Dictionary(m.map { ($0.key, $0.value) }, uniquingKeysWith: { a, _ in a })
            func num(_ v: JSONValue?) -> Double? { if case .number(let x, _)? = v, x.isFinite { return x }; return nil }
            func str(_ v: JSONValue?) -> String? {
                if case .string(let s)? = v { return s }
                // An integer written as a number ("floor": 2); one beyond Int (1e20 written out) is not a name.
                if case .number(let x, true)? = v, let i = Int(exactly: x) { return String(i) }
                return nil
            }
            guard let number = num(d["id"]).flatMap({ Int(exactly: $0) }) ?? Int(key) else { throw bad("node \(key) has no integer 'id'") }
            guard let type = str(d["type"]) else { throw bad("node \(key) has no 'type'") }
            guard case .array(let p)? = d["position"], p.count == 2, let col = num(p[0]), let row = num(p[1]) else {
                throw bad("node \(key): 'position' must be [column, row] in pixels")
            }
            guard let floor = str(d["floor"]) else { throw bad("node \(key) has no 'floor'") }
            let label = str(d["label"]) ?? ""
            let isDoor = (num(d["isDoor"]) ?? 0) != 0
            raw.append(RawNode(number: number, type: type, col: col, row: row, floor: floor, label: label, isDoor: isDoor))
        }
        raw.sort { $0.number < $1.number }
        let n = raw.count
        guard n > 0 else { throw bad("no nodes") }
        guard raw.map(\.number) == Array(1...n) else { throw bad("node ids must be 1...\(n) (the weights matrix is indexed by id - 1)") }
        guard weightRows.count == n else { throw bad("'weights' has \(weightRows.count) rows for \(n) nodes") }
        var weights: [[Double]] = []
        for (i, r) in weightRows.enumerated() {
            guard case .array(let cells) = r, cells.count == n else { throw bad("'weights' row \(i) must have \(n) numbers") }
            weights.append(try cells.map { c in
                guard case .number(let x, _) = c, x.isFinite, x >= 0 else { throw bad("'weights' row \(i) holds a non-number or negative weight") }
                return x
            })
        }

        var floorsById = Dictionary(uniqueKeysWithValues: sources.map { ($0.id, $0) })
        var nodes: [GraphNode] = []
        var poisByFloor: [String: [PointOfInterest]] = [:]
        var usedPoiIds = Set<String>()
        for r in raw {
            guard let src = floorsById[r.floor] else { throw bad("node \(r.number) is on floor '\(r.floor)', which info.yml does not list") }
            let pos = Point2(r.col / src.scale, (Double(src.rows) - r.row) / src.scale)
            let nodeId = "node-\(r.number)"
            let numericLabel = Int(r.label) != nil
            switch r.type {
            case "control":
                nodes.append(GraphNode(id: nodeId, kind: .control, floorId: r.floor, position: pos, label: numericLabel || r.label.isEmpty ? nil : r.label))
            case "destination":
                let name = numericLabel || r.label.isEmpty ? "Destination \(r.number)" : capitalizedFirst(r.label)
                var poiId = "\(slug(name))-\(r.floor)f"
                if usedPoiIds.contains(poiId) { poiId = "\(slug(name))-\(r.floor)f-\(r.number)" }
                usedPoiIds.insert(poiId)
                poisByFloor[r.floor, default: []].append(PointOfInterest(id: poiId, name: name, category: category(of: r.label, isDoor: r.isDoor),
                                                                         position: pos, behindDoor: r.isDoor))
                nodes.append(GraphNode(id: nodeId, kind: .pointOfInterest, floorId: r.floor, position: pos, label: name, pointOfInterestId: poiId))
            case "link":
                let l = r.label.lowercased()
                let kind: VerticalLinkKind
                if l.contains("elevator") || l.contains("lift") { kind = .elevator } else if l.contains("stair") { kind = .stairs } else {
                    throw bad("link node \(r.number) label '\(r.label)' says neither elevator nor stairs")
                }
                nodes.append(GraphNode(id: nodeId, kind: .verticalLink, floorId: r.floor, position: pos,
                                       label: r.label.isEmpty ? nil : capitalizedFirst(r.label), verticalLink: kind))
            default:
                throw bad("node \(r.number) has unknown type '\(r.type)' (control, destination or link)")
            }
        }
        var edges: [GraphEdge] = []
        for i in 0..<n {
            for j in (i + 1)..<n where weights[i][j] != 0 || weights[j][i] != 0 {
                let door = (raw[i].type == "destination" && raw[i].isDoor) || (raw[j].type == "destination" && raw[j].isDoor)
                edges.append(GraphEdge(from: "node-\(i + 1)", to: "node-\(j + 1)", throughDoor: door))
            }
        }
        // Vertical edges: link nodes sharing a label, consecutive floors.
        let links = raw.filter { $0.type == "link" }
        for (_, group) in Dictionary(grouping: links, by: { $0.label.lowercased() }).sorted(by: { $0.key < $1.key }) {
            let sorted = group.sorted { floorsById[$0.floor]!.number < floorsById[$1.floor]!.number }
            for (a, b) in zip(sorted, sorted.dropFirst()) where a.floor != b.floor {
                edges.append(GraphEdge(from: "node-\(a.number)", to: "node-\(b.number)", throughDoor: false))
            }
        }

        for (id, pois) in poisByFloor {
            let s = floorsById[id]!
            var f = s.floor
            f.pointsOfInterest = pois
            floorsById[id] = FloorSource(id: s.id, number: s.number, scale: s.scale, rows: s.rows, floor: f)
        }
        let floors = sources.map { floorsById[$0.id]!.floor }
        // info.yml's angle_to_north (degrees, one per floor): read as the clockwise angle from the plan's up (+y)
        // to north, so a compass facing +y reads 360 - angle. The sign convention is not documented by the
        // source and could not be checked against recordings; at SKERI's 9.1 degrees a wrong sign costs 18
        // degrees, inside the compass prior's spread (docs/localizer.md). Kept only when all floors agree.
        var compassHeadingOfMapNorthDeg: Double?
        if let first = anglesToNorthDeg.first, anglesToNorthDeg.count == floorRecords.count,
           anglesToNorthDeg.allSatisfy({ abs($0 - first) < 1e-9 }) {
            let h = (360 - first).truncatingRemainder(dividingBy: 360)
            compassHeadingOfMapNorthDeg = h < 0 ? h + 360 : h
        }
        let building = Building(id: slug(buildingName), name: buildingName, floors: floors, graph: NavigationGraph(nodes: nodes, edges: edges),
                                compassHeadingOfMapNorthDeg: compassHeadingOfMapNorthDeg)
        try MapValidator.validate(building, file: "\(buildingName) (imported from \(dir.path))")
        let report = floors.map { f in
            FloorReport(floorId: f.id, walls: f.walls.count, signs: f.signs.count, signAdjustmentsMeters: reports[f.id]?.signs ?? [],
                        pointsOfInterest: f.pointsOfInterest.count, nodes: nodes.filter { $0.floorId == f.id }.count)
        }
        return (building, report)
    }

    /// Category of a destination from its label: restroom, stairs, elevator, exit, office, else room
    /// (behind a door) or amenity (coffee machine, water cooler...).
    public static func category(of label: String, isDoor: Bool) -> String {
        let l = label.lowercased()
        if l.contains("restroom") || l.contains("toilet") || l.contains("bathroom") { return "restroom" }
        if l.contains("stair") { return "stairs" }
        if l.contains("elevator") || l.contains("lift") { return "elevator" }
        if l.contains("exit") || l.contains("entrance") { return "exit" }
        if l.contains("office") || l.contains("cubicle") { return "office" }
        return isDoor ? "room" : "amenity"
    }

    /// Lower-case ASCII id from a label: letters and digits kept, runs of anything else -> "-",
    /// apostrophes dropped ("Men's restroom" -> "mens-restroom").
    public static func slug(_ s: String) -> String {
        var out = ""
        var pendingDash = false
        for ch in s.lowercased() {
            if ch == "'" || ch == "\u{2019}" { continue }
            if ch.isASCII && (ch.isLetter || ch.isNumber) {
                if pendingDash && !out.isEmpty { out.append("-") }
                pendingDash = false
                out.append(ch)
            } else {
                pendingDash = true
            }
        }
        return out.isEmpty ? "unnamed" : out
    }

    static func capitalizedFirst(_ s: String) -> String {
        guard let f = s.first else { return s }
        return f.uppercased() + s.dropFirst()
    }

    static func yaml(_ url: URL) throws -> SimpleYAML {
        guard FileManager.default.fileExists(atPath: url.path) else { throw InavigateImportError(file: url.path, reason: "no such file") }
        guard let data = try? Data(contentsOf: url) else { throw InavigateImportError(file: url.path, reason: "cannot read the file") }
        guard let text = String(data: data, encoding: .utf8) else { throw InavigateImportError(file: url.path, reason: "not UTF-8 text") }
        do { return try SimpleYAML(text: text, file: url.path) } catch let e as SimpleYAML.ParseError {
            throw InavigateImportError(file: url.path, reason: "line \(e.line): \(e.reason)")
        }
    }

    /// Where a sign surveyed at `p` facing `facing` sits on a wall, or nil when no wall face is within
    /// `maximumMeters` (a projecting sign). First choice: the wall face straight behind the sign (the first
    /// wall hit by the ray from `p` along -facing), so the sign moves only along its normal; otherwise the
    /// closest point of the nearest wall segment whose free side faces the sign's normal (the point half a
    /// pixel in front of it is not wall).
    static func snap(_ p: Point2, facing: Point2, walls: [Wall], mask: [Bool], width: Int, height: Int, scale: Double,
                     maximumMeters: Double) -> Point2? {
        func isWall(_ q: Point2) -> Bool {
            let c = Int((q.x * scale).rounded(.down)), r = Int((Double(height) - q.y * scale).rounded(.down))
            return c >= 0 && r >= 0 && c < width && r < height && mask[r * width + c]
        }
        let behind = Point2(p.x - facing.x * maximumMeters, p.y - facing.y * maximumMeters)
        var bestT = Double.infinity
        var hit: Point2?
        for w in walls {
            if let x = Geometry.segmentIntersection(p, behind, w.from, w.to), x.t < bestT { bestT = x.t; hit = x.point }
        }
        if let h = hit { return h }
        let step = 0.5 / scale
        var candidates: [(Double, Point2)] = []
        for w in walls {
            let q = w.closestPoint(to: p)
            let d = q.distance(to: p)
            if d <= maximumMeters { candidates.append((d, q)) }
        }
        candidates.sort { $0.0 < $1.0 }
        for (_, q) in candidates where !isWall(Point2(q.x + facing.x * step, q.y + facing.y * step)) { return q }
        return nil
    }
}
