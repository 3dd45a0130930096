// Map format v1: the in-memory model. Units are meters; the map frame is right-handed with x east (right
// on the floor plan) and y north (up on the floor plan). Angles are radians, counter-clockwise from +x.
// Loading and validation live in MapLoader.swift / MapValidation.swift; the JSON Schema is
// Maps/schema/map-v1.schema.json and docs/map-format.md describes it for people.

/// A point or direction in the map frame of one floor, meters.
public struct Point2: Hashable, Sendable {
    /// East (right on the plan), meters.
    public var x: Double
    /// North (up on the plan), meters.
    public var y: Double
    /// Creates a point from its map-frame coordinates in meters.
    public init(x: Double, y: Double) { self.x = x; self.y = y }
    /// Creates a point from an `[x, y]` pair.
    public init(_ x: Double, _ y: Double) { self.x = x; self.y = y }
}

extension Point2: Codable {
    /// Decodes the JSON form `[x, y]`.
    public init(from decoder: Decoder) throws {
        var c = try decoder.unkeyedContainer()
        x = try c.decode(Double.self)
        y = try c.decode(Double.self)
        if !c.isAtEnd {
            throw DecodingError.dataCorruptedError(in: c, debugDescription: "a point has exactly two numbers [x, y]")
        }
    }
    /// Encodes as `[x, y]`.
    public func encode(to encoder: Encoder) throws {
        var c = encoder.unkeyedContainer()
        try c.encode(x)
        try c.encode(y)
    }
}

/// A whole building: floors and the navigation graph joining them.
public struct Building: Codable, Equatable, Sendable {
    /// Format version of the file this came from; this code reads and writes 1.
    public var formatVersion: Int
    /// Stable identifier, referenced by recorded sessions (`session.json` `mapId`).
    public var id: String
    /// Human-readable name, spoken to the traveler.
    public var name: String
    /// Floors, each with its own map frame (same axes, same origin above one another).
    public var floors: [Floor]
    /// Navigation graph over all floors.
    public var graph: NavigationGraph
    /// What a compass reads when the phone faces the map's +y axis: degrees clockwise from magnetic north, in
    /// [0, 360). nil when the plan's orientation is unknown; the localizer then uses no compass prior.
    public var compassHeadingOfMapNorthDeg: Double?
    /// The sign-kind catalogue as the map states it ("signKinds": each kind's face size, colours, sidedness), or
    /// nil when the map has none; `signCatalogue` (SignCatalogue.swift) resolves it with defaults.
    public var signKinds: [SignKindSpec]?

    /// Creates a building from its parts (no validation; see `MapLoader`).
    public init(formatVersion: Int = 1, id: String, name: String, floors: [Floor], graph: NavigationGraph,
                compassHeadingOfMapNorthDeg: Double? = nil, signKinds: [SignKindSpec]? = nil) {
        self.formatVersion = formatVersion; self.id = id; self.name = name; self.floors = floors; self.graph = graph
        self.compassHeadingOfMapNorthDeg = compassHeadingOfMapNorthDeg; self.signKinds = signKinds
    }

    /// The floor with this id, if any.
    public func floor(id floorId: String) -> Floor? { floors.first { $0.id == floorId } }
}

/// One storey.
public struct Floor: Codable, Equatable, Sendable {
    /// Identifier unique in the building (e.g. "3").
    public var id: String
    /// Spoken name ("Floor 3", "Ground floor").
    public var name: String
    /// Height of this floor above the building's reference, meters (used for barometric floor changes).
    public var elevationMeters: Double
    /// Walls and other impassable barriers as line segments.
    public var walls: [Wall]
    /// Doors and openings (informational; a passable door is a gap between wall segments).
    public var doors: [Door]
    /// Signs mounted on walls (Exit signs and, later, other kinds).
    public var signs: [Sign]
    /// Labelled places a traveler can choose as start or destination.
    public var pointsOfInterest: [PointOfInterest]

    /// Creates a floor from its parts.
    public init(id: String, name: String, elevationMeters: Double, walls: [Wall], doors: [Door] = [],
                signs: [Sign] = [], pointsOfInterest: [PointOfInterest] = []) {
        self.id = id; self.name = name; self.elevationMeters = elevationMeters; self.walls = walls
        self.doors = doors; self.signs = signs; self.pointsOfInterest = pointsOfInterest
    }
}

/// An impassable, opaque line segment (a wall face), meters in the floor's map frame.
public struct Wall: Codable, Hashable, Sendable {
    /// One end.
    public var from: Point2
    /// The other end.
    public var to: Point2
    /// Creates a wall segment.
    public init(from: Point2, to: Point2) { self.from = from; self.to = to }
    /// Length in meters.
    public var lengthMeters: Double { ((to.x - from.x) * (to.x - from.x) + (to.y - from.y) * (to.y - from.y)).squareRoot() }
}

/// A door or opening in a wall.
public struct Door: Codable, Hashable, Sendable {
    /// Identifier unique on the floor.
    public var id: String
    /// Centre of the opening, meters.
    public var position: Point2
    /// Clear width of the opening, meters.
    public var widthMeters: Double
    /// Optional spoken label ("Main entrance").
    public var label: String?
    /// Creates a door.
    public init(id: String, position: Point2, widthMeters: Double, label: String? = nil) {
        self.id = id; self.position = position; self.widthMeters = widthMeters; self.label = label
    }
}

/// A sign mounted on a wall.
public struct Sign: Codable, Hashable, Sendable {
    /// Identifier unique on the floor.
    public var id: String
    /// Sign class, e.g. `exit`. Detections carry the same kind string.
    public var kind: String
    /// Centre of the sign's face projected on the floor plan, meters (on or within a few cm of a wall).
    public var position: Point2
    /// Unit normal of the face, pointing into the space from which the sign can be read.
    public var facing: Point2
    /// Physical width of the face, meters.
    public var widthMeters: Double
    /// Physical height of the face (h0 of the range formula), meters.
    public var heightMeters: Double
    /// Height of the face's bottom edge above the floor, meters, when surveyed.
    public var mountingHeightMeters: Double?
    /// True when the sign can be read from both sides (hung from the ceiling, or printed on both faces).
    public var doubleSided: Bool
    /// How far an importer moved the surveyed position to put the sign on its wall, meters; nil when the
    /// position was not adjusted (hand-made maps). Informational: the localizer uses `position` only.
    public var positionAdjustmentMeters: Double? = nil
    /// How the sign is mounted: flat on a wall (the default) or projecting into the corridor (flag mount,
    /// ceiling-hung). Sets how far from a wall `MapValidator` lets `position` be.
    public var placement: SignPlacement = .wall
    /// The sign's legend when it identifies the sign, e.g. a room-number placard's "402"; nil for signs that
    /// look alike (Exit signs, pictograms). Unique per kind on a floor (`MapValidator`): a sighting that reads
    /// it can only be this sign, so the localizer matches it to this sign alone.
    public var text: String? = nil
    /// Creates a sign.
    public init(id: String, kind: String, position: Point2, facing: Point2, widthMeters: Double, heightMeters: Double,
                mountingHeightMeters: Double? = nil, doubleSided: Bool = false) {
        self.id = id; self.kind = kind; self.position = position; self.facing = facing; self.widthMeters = widthMeters
        self.heightMeters = heightMeters; self.mountingHeightMeters = mountingHeightMeters; self.doubleSided = doubleSided
    }
}

/// How a sign is mounted. JSON: "wall" (default when absent) or "projecting".
public enum SignPlacement: String, Codable, Sendable {
    /// Flat on a wall face: `position` lies within `MapValidator.maximumSignDistanceFromWallMeters` (0.3 m)
    /// of a wall segment, `facing` points away from that wall.
    case wall
    /// Projecting into the space: a flag sign perpendicular to its wall or a sign hung from the ceiling over
    /// a corridor; `position` is the face centre in the open, within
    /// `MapValidator.maximumProjectingSignDistanceFromWallMeters` (1.5 m) of a wall.
    case projecting
}

/// A labelled place (room, restroom, elevator lobby...).
public struct PointOfInterest: Codable, Hashable, Sendable {
    /// Identifier unique in the building.
    public var id: String
    /// Spoken name ("Room 312", "Women's restroom").
    public var name: String
    /// Category ("room", "restroom", "elevator", "stairs", "exit", "office", ...).
    public var category: String
    /// Position of the place's entrance, meters.
    public var position: Point2
    /// True when the place is behind a door (announced on arrival).
    public var behindDoor: Bool
    /// Creates a point of interest.
    public init(id: String, name: String, category: String, position: Point2, behindDoor: Bool) {
        self.id = id; self.name = name; self.category = category; self.position = position; self.behindDoor = behindDoor
    }
}

/// The navigation graph: nodes on floors and edges between them.
public struct NavigationGraph: Codable, Equatable, Sendable {
    /// Nodes of every floor.
    public var nodes: [GraphNode]
    /// Undirected edges; lengths are derived from node positions (see `GraphEdge`).
    public var edges: [GraphEdge]
    /// Creates a graph.
    public init(nodes: [GraphNode], edges: [GraphEdge]) { self.nodes = nodes; self.edges = edges }
}

/// What a graph node stands for.
public enum GraphNodeKind: String, Codable, Sendable {
    /// A point of interest (destination); `pointOfInterestId` names it.
    case pointOfInterest
    /// A control point: corridor junction or corner where a maneuver may be announced.
    case control
    /// An elevator or stairs landing; `verticalLink` says which and links it across floors.
    case verticalLink
}

/// Elevator or stairs.
public enum VerticalLinkKind: String, Codable, Sendable {
    /// An elevator.
    case elevator
    /// A staircase.
    case stairs
}

/// A node of the navigation graph.
public struct GraphNode: Codable, Hashable, Sendable {
    /// Identifier unique in the building.
    public var id: String
    /// Role of the node.
    public var kind: GraphNodeKind
    /// Floor the node is on.
    public var floorId: String
    /// Position, meters in the floor's map frame.
    public var position: Point2
    /// Optional spoken label ("Elevator", "Stairwell B", "Room 312").
    public var label: String?
    /// For `pointOfInterest` nodes: the point of interest's id.
    public var pointOfInterestId: String?
    /// For `verticalLink` nodes: elevator or stairs.
    public var verticalLink: VerticalLinkKind?
    /// Creates a node.
    public init(id: String, kind: GraphNodeKind, floorId: String, position: Point2, label: String? = nil,
                pointOfInterestId: String? = nil, verticalLink: VerticalLinkKind? = nil) {
        self.id = id; self.kind = kind; self.floorId = floorId; self.position = position; self.label = label
        self.pointOfInterestId = pointOfInterestId; self.verticalLink = verticalLink
    }
}

/// An undirected edge. Its length is derived: the horizontal distance between the nodes on one floor;
/// for an edge between two vertical-link nodes on different floors, the elevation difference.
public struct GraphEdge: Codable, Hashable, Sendable {
    /// One end's node id.
    public var from: String
    /// The other end's node id.
    public var to: String
    /// True when walking the edge passes through a door.
    public var throughDoor: Bool
    /// Creates an edge.
    public init(from: String, to: String, throughDoor: Bool = false) { self.from = from; self.to = to; self.throughDoor = throughDoor }
}

// Decodable with the same defaults as MapLoader for optional members (for code that uses JSONDecoder
// directly; it does not validate: use MapLoader for files from outside).
extension Floor {
    /// Decodes a floor; `doors`, `signs` and `pointsOfInterest` default to empty.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        self.init(id: try c.decode(String.self, forKey: .id), name: try c.decode(String.self, forKey: .name),
                  elevationMeters: try c.decode(Double.self, forKey: .elevationMeters), walls: try c.decode([Wall].self, forKey: .walls),
                  doors: try c.decodeIfPresent([Door].self, forKey: .doors) ?? [],
                  signs: try c.decodeIfPresent([Sign].self, forKey: .signs) ?? [],
                  pointsOfInterest: try c.decodeIfPresent([PointOfInterest].self, forKey: .pointsOfInterest) ?? [])
    }
}

extension Sign {
    /// Decodes a sign; `doubleSided` defaults to false, `placement` to `.wall`, `text` to nil.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        self.init(id: try c.decode(String.self, forKey: .id), kind: try c.decode(String.self, forKey: .kind),
                  position: try c.decode(Point2.self, forKey: .position), facing: try c.decode(Point2.self, forKey: .facing),
                  widthMeters: try c.decode(Double.self, forKey: .widthMeters), heightMeters: try c.decode(Double.self, forKey: .heightMeters),
                  mountingHeightMeters: try c.decodeIfPresent(Double.self, forKey: .mountingHeightMeters),
                  doubleSided: try c.decodeIfPresent(Bool.self, forKey: .doubleSided) ?? false)
        positionAdjustmentMeters = try c.decodeIfPresent(Double.self, forKey: .positionAdjustmentMeters)
        placement = try c.decodeIfPresent(SignPlacement.self, forKey: .placement) ?? .wall
        text = try c.decodeIfPresent(String.self, forKey: .text)
    }
}

extension PointOfInterest {
    /// Decodes a point of interest; `behindDoor` defaults to false.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        self.init(id: try c.decode(String.self, forKey: .id), name: try c.decode(String.self, forKey: .name),
                  category: try c.decode(String.self, forKey: .category), position: try c.decode(Point2.self, forKey: .position),
                  behindDoor: try c.decodeIfPresent(Bool.self, forKey: .behindDoor) ?? false)
    }
}

extension GraphEdge {
    /// Decodes an edge; `throughDoor` defaults to false.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        self.init(from: try c.decode(String.self, forKey: .from), to: try c.decode(String.self, forKey: .to),
                  throughDoor: try c.decodeIfPresent(Bool.self, forKey: .throughDoor) ?? false)
    }
}
