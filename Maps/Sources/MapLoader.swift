import Foundation

/// Reads map format v1 files (see docs/map-format.md and Maps/schema/map-v1.schema.json).
///
/// Loading is all-or-nothing: the file is parsed by a strict JSON reader, every member is type-checked
/// while walking the document (so errors name the exact JSON path), and the resulting `Building` is then
/// checked by `MapValidator`. The first problem found is thrown as one `MapError` naming the file, the
/// JSON path and the reason.
public enum MapLoader {
    /// The only format version this code reads and writes.
    public static let supportedFormatVersion = 1

    /// Largest map file accepted, bytes (64 MiB; the imported Smith-Kettlewell building is about 0.25 MB).
    /// Reading stops there, so a huge or endless input (`/dev/zero`) is refused rather than read into memory.
    public static let maximumFileBytes = 64 << 20

    /// Loads and validates the map file at `url`. Errors name the file by its last path component.
    ///
    /// Only a regular file (or a symbolic link to one) is read: a FIFO, device, socket or directory is refused
    /// without reading (a FIFO would block, `/dev/zero` never end), as is a file over `maximumFileBytes`.
    /// - Throws: `MapError` (unreadable file, bad JSON, schema or consistency violation).
    public static func load(contentsOf url: URL) throws -> Building {
        let name = url.lastPathComponent.isEmpty ? url.path : url.lastPathComponent
        let data: Data
        do {
            data = try MapFileReader.read(path: url.path, limitBytes: maximumFileBytes)
        } catch let e as MapFileReader.Failure {
            throw MapError(file: name, jsonPath: "$", reason: e.reason)
        }
        return try load(data: data, fileName: name)
    }

    /// Loads and validates a map from the bytes of a file; `fileName` is used in error messages only.
    /// - Throws: `MapError`.
    public static func load(data: Data, fileName: String) throws -> Building {
        let root: JSONValue
        do {
            root = try JSONParser.parse([UInt8](data))
        } catch let e as JSONSyntaxError {
            throw MapError(file: fileName, jsonPath: "$", reason: "not valid JSON: \(e.description)")
        }
        let building: Building
        do {
            building = try MapDocumentDecoder.decodeBuilding(root)
        } catch let e as PathError {
            throw e.mapError(file: fileName)
        }
        try MapValidator.validate(building, file: fileName)
        return building
    }
}

/// Walks a parsed JSON document into model values, naming the JSON path of any type error.
enum MapDocumentDecoder {
    /// One JSON object being read: tracks which members were consumed so unknown ones can be reported.
    struct ObjectReader {
        let members: [String: JSONValue]
        let order: [String]
        let path: String
        private(set) var used = Set<String>()

        init(_ value: JSONValue, path: String) throws {
            guard case .object(let m) = value else {
                throw PathError(path: path, reason: "expected an object, got \(value.typeDescription)")
            }
            var d: [String: JSONValue] = [:]
            for (k, v) in m { d[k] = v }
            members = d; order = m.map { $0.key }; self.path = path
        }

        func childPath(_ key: String) -> String { "\(path).\(key)" }

        mutating func optional(_ key: String) -> JSONValue? {
            used.insert(key)
            guard let v = members[key] else { return nil }
            if case .null = v { return nil }
            return v
        }

        mutating func required(_ key: String) throws -> JSONValue {
            used.insert(key)
            guard let v = members[key] else {
                throw PathError(path: childPath(key), reason: "missing required field '\(key)'")
            }
            if case .null = v { throw PathError(path: childPath(key), reason: "required field '\(key)' is null") }
            return v
        }

        mutating func string(_ key: String) throws -> String {
            try MapDocumentDecoder.string(try required(key), path: childPath(key))
        }

        mutating func optionalString(_ key: String) throws -> String? {
            guard let v = optional(key) else { return nil }
            return try MapDocumentDecoder.string(v, path: childPath(key))
        }

        mutating func number(_ key: String) throws -> Double {
            try MapDocumentDecoder.number(try required(key), path: childPath(key))
        }

        mutating func optionalNumber(_ key: String) throws -> Double? {
            guard let v = optional(key) else { return nil }
            return try MapDocumentDecoder.number(v, path: childPath(key))
        }

        mutating func bool(_ key: String, default d: Bool) throws -> Bool {
            guard let v = optional(key) else { return d }
            guard case .bool(let b) = v else {
                throw PathError(path: childPath(key), reason: "expected true or false, got \(v.typeDescription)")
            }
            return b
        }

        mutating func point(_ key: String) throws -> Point2 {
            try MapDocumentDecoder.point(try required(key), path: childPath(key))
        }

        mutating func array(_ key: String, required isRequired: Bool = true) throws -> [(JSONValue, String)] {
            let v: JSONValue
            if isRequired { v = try required(key) } else {
                guard let o = optional(key) else { return [] }
                v = o
            }
            guard case .array(let items) = v else {
                throw PathError(path: childPath(key), reason: "expected an array, got \(v.typeDescription)")
            }
            return items.enumerated().map { ($0.element, "\(childPath(key))[\($0.offset)]") }
        }

        /// Throws on a member that was never read, unless it is `$schema` or starts with `x-` (extensions).
        func rejectUnknownMembers() throws {
            for k in order where !used.contains(k) && k != "$schema" && !k.hasPrefix("x-") {
                throw PathError(path: childPath(k), reason: "unknown field '\(k)' (extensions must start with 'x-')")
            }
        }
    }

    static func string(_ v: JSONValue, path: String) throws -> String {
        guard case .string(let s) = v else { throw PathError(path: path, reason: "expected a string, got \(v.typeDescription)") }
        return s
    }

    static func number(_ v: JSONValue, path: String) throws -> Double {
        switch v {
        case .number(let d, _):
            guard d.isFinite else { throw PathError(path: path, reason: "number out of range (not representable as a finite double)") }
            return d
        case .string(let s):
            if let d = Double(s.trimmingCharacters(in: .whitespaces)), !d.isFinite || s.lowercased().contains("nan") || s.lowercased().contains("inf") {
                throw PathError(path: path, reason: "expected a finite number, got the string \"\(s)\" (NaN and infinity are not allowed)")
            }
            throw PathError(path: path, reason: "expected a number, got a string (\"\(s)\")")
        default:
            throw PathError(path: path, reason: "expected a number, got \(v.typeDescription)")
        }
    }

    static func point(_ v: JSONValue, path: String) throws -> Point2 {
        guard case .array(let items) = v else {
            throw PathError(path: path, reason: "expected a point [x, y] (an array of two numbers), got \(v.typeDescription)")
        }
        guard items.count == 2 else {
            throw PathError(path: path, reason: "expected a point [x, y] (two numbers), got \(items.count) element(s)")
        }
        return Point2(try number(items[0], path: "\(path)[0]"), try number(items[1], path: "\(path)[1]"))
    }

    static func decodeBuilding(_ root: JSONValue) throws -> Building {
        var o = try ObjectReader(root, path: "$")
        let versionValue = try o.required("formatVersion")
        guard case .number(let v, let isInteger) = versionValue, isInteger, v.isFinite else {
            throw PathError(path: "$.formatVersion", reason: "formatVersion must be the integer \(MapLoader.supportedFormatVersion), got \(versionValue.typeDescription)")
        }
        guard v == Double(MapLoader.supportedFormatVersion) else {
            throw PathError(path: "$.formatVersion", reason: "unsupported formatVersion \(Int(exactly: v).map(String.init) ?? String(v)); this build reads version \(MapLoader.supportedFormatVersion)")
        }
        let id = try o.string("id")
        let name = try o.string("name")
        let floors = try o.array("floors").map { try decodeFloor($0.0, path: $0.1) }
        let northDeg = try o.optionalNumber("compassHeadingOfMapNorthDeg")
        if let d = northDeg, !(d >= 0 && d < 360) {
            throw PathError(path: "$.compassHeadingOfMapNorthDeg", reason: "compassHeadingOfMapNorthDeg must be in [0, 360) degrees, got \(d)")
        }
        let signKinds = try (o.optional("signKinds") == nil ? nil : o.array("signKinds"))?.map { (v, p) -> SignKindSpec in
            var k = try ObjectReader(v, path: p)
            let spec = SignKindSpec(kind: try k.string("kind"), heightMeters: try k.number("heightMeters"),
                                    widthMeters: try k.number("widthMeters"), faceColor: try k.optionalString("faceColor"),
                                    legendColor: try k.optionalString("legendColor"),
                                    doubleSided: try k.bool("doubleSided", default: false),
                                    maxRangeMeters: try k.optionalNumber("maxRangeMeters"),
                                    maxViewAngleDeg: try k.optionalNumber("maxViewAngleDeg"),
                                    mountingHeightMeters: try k.optionalNumber("mountingHeightMeters"),
                                    readsText: try k.bool("readsText", default: false))
            try k.rejectUnknownMembers()
            return spec
        }
        var g = try ObjectReader(try o.required("graph"), path: "$.graph")
        let nodes = try g.array("nodes").map { try decodeNode($0.0, path: $0.1) }
        let edges = try g.array("edges").map { try decodeEdge($0.0, path: $0.1) }
        try g.rejectUnknownMembers()
        try o.rejectUnknownMembers()
        return Building(formatVersion: Int(v), id: id, name: name, floors: floors,
                        graph: NavigationGraph(nodes: nodes, edges: edges), compassHeadingOfMapNorthDeg: northDeg,
                        signKinds: signKinds)
    }

    static func decodeFloor(_ value: JSONValue, path: String) throws -> Floor {
        var o = try ObjectReader(value, path: path)
        let id = try o.string("id")
        let name = try o.string("name")
        let elevation = try o.number("elevationMeters")
        let walls = try o.array("walls").map { (v, p) -> Wall in
            var w = try ObjectReader(v, path: p)
            let wall = Wall(from: try w.point("from"), to: try w.point("to"))
            try w.rejectUnknownMembers()
            return wall
        }
        let doors = try o.array("doors", required: false).map { (v, p) -> Door in
            var d = try ObjectReader(v, path: p)
            let door = Door(id: try d.string("id"), position: try d.point("position"), widthMeters: try d.number("widthMeters"),
                            label: try d.optionalString("label"))
            try d.rejectUnknownMembers()
            return door
        }
        let signs = try o.array("signs", required: false).map { (v, p) -> Sign in
            var s = try ObjectReader(v, path: p)
            var sign = Sign(id: try s.string("id"), kind: try s.string("kind"), position: try s.point("position"),
                            facing: try s.point("facing"), widthMeters: try s.number("widthMeters"),
                            heightMeters: try s.number("heightMeters"),
                            mountingHeightMeters: try s.optionalNumber("mountingHeightMeters"),
                            doubleSided: try s.bool("doubleSided", default: false))
            sign.positionAdjustmentMeters = try s.optionalNumber("positionAdjustmentMeters")
            sign.text = try s.optionalString("text")
            if let t = try s.optionalString("placement") {
                guard let pl = SignPlacement(rawValue: t) else {
                    throw PathError(path: "\(p).placement", reason: "unknown sign placement \"\(t)\" (expected wall or projecting)")
                }
                sign.placement = pl
            }
            try s.rejectUnknownMembers()
            return sign
        }
        let pois = try o.array("pointsOfInterest", required: false).map { (v, p) -> PointOfInterest in
            var q = try ObjectReader(v, path: p)
            let poi = PointOfInterest(id: try q.string("id"), name: try q.string("name"), category: try q.string("category"),
                                      position: try q.point("position"), behindDoor: try q.bool("behindDoor", default: false))
            try q.rejectUnknownMembers()
            return poi
        }
        try o.rejectUnknownMembers()
        return Floor(id: id, name: name, elevationMeters: elevation, walls: walls, doors: doors, signs: signs,
                     pointsOfInterest: pois)
    }

    static func decodeNode(_ value: JSONValue, path: String) throws -> GraphNode {
        var o = try ObjectReader(value, path: path)
        let id = try o.string("id")
        let kindText = try o.string("kind")
        guard let kind = GraphNodeKind(rawValue: kindText) else {
            throw PathError(path: "\(path).kind", reason: "unknown node kind \"\(kindText)\" (expected pointOfInterest, control or verticalLink)")
        }
        let floorId = try o.string("floorId")
        let position = try o.point("position")
        let label = try o.optionalString("label")
        let poiId = try o.optionalString("pointOfInterestId")
        var link: VerticalLinkKind?
        if let t = try o.optionalString("verticalLink") {
            guard let k = VerticalLinkKind(rawValue: t) else {
                throw PathError(path: "\(path).verticalLink", reason: "unknown vertical link \"\(t)\" (expected elevator or stairs)")
            }
            link = k
        }
        try o.rejectUnknownMembers()
        return GraphNode(id: id, kind: kind, floorId: floorId, position: position, label: label,
                         pointOfInterestId: poiId, verticalLink: link)
    }

    static func decodeEdge(_ value: JSONValue, path: String) throws -> GraphEdge {
        var o = try ObjectReader(value, path: path)
        let e = GraphEdge(from: try o.string("from"), to: try o.string("to"), throughDoor: try o.bool("throughDoor", default: false))
        try o.rejectUnknownMembers()
        return e
    }
}
