// Stage 1 of guidance (after OSRM and valhalla): route geometry becomes typed maneuvers, with no text.
// Stage 2 (Narrative.swift) turns maneuvers into phrases from a per-language template file.
import Foundation
import Maps

/// What the traveler does at a maneuver. Raw values are the keys of the phrase files
/// (`Navigation/Locales/<language>.json`, section `maneuvers`) and the names used in test tables.
public enum ManeuverKind: String, Sendable, Equatable, CaseIterable, Codable {
    /// Start of the route; its direction is given relative to the traveler's heading when spoken.
    case depart
    /// Walk on after leaving an elevator or stairs (the landing, where no turn angle exists).
    case `continue`
    /// Change of direction 45-135 deg to the left.
    case turnLeft
    /// Change of direction 45-135 deg to the right.
    case turnRight
    /// 20-45 deg to the left ("bear left"); also a short jog of the corridor to the left.
    case slightLeft
    /// 20-45 deg to the right ("bear right"); also a short jog of the corridor to the right.
    case slightRight
    /// 135-170 deg to the left.
    case sharpLeft
    /// 135-170 deg to the right.
    case sharpRight
    /// More than 170 deg either way.
    case uTurn
    /// Ride an elevator to another floor (`Maneuver.toFloorId`).
    case takeElevator
    /// Take stairs to another floor (`Maneuver.toFloorId`).
    case takeStairs
    /// Pass through a door on the way.
    case goThroughDoor
    /// The destination.
    case arrive

    /// True for the kinds produced by `TurnClassifier`.
    public var isTurn: Bool {
        switch self {
        case .turnLeft, .turnRight, .slightLeft, .slightRight, .sharpLeft, .sharpRight, .uTurn: return true
        default: return false
        }
    }
}

/// Classifies a change of direction at a control point.
///
/// Convention: the signed turn angle is the change of walking direction from the incoming to the outgoing
/// segment, `atan2(cross(in, out), dot(in, out))`, in degrees in (-180, 180]; POSITIVE = LEFT
/// (counter-clockwise in the map frame, x east, y north), negative = right. 0 = straight on.
///
/// Thresholds on |angle| (degrees):
/// - below 20: straight, no maneuver. The reference app (iNavigate `NavigationSystem::calculateTurn`)
///   treats +-20 deg as "forward"; OSRM's `getTurnDirection` uses +-22.5 deg (a 45 deg sector) for
///   straight. Corridors drawn on a floor plan bend by a few degrees without being a turn.
/// - 20 to 45: slight ("bear"). iNavigate's (disabled) "easy left/right" band ends at 45 deg.
/// - 45 to 135: turn. Centred on the right angle of most corridor junctions, +-45 deg, so a junction
///   drawn a little skew is still "turn left"; OSRM's 67.5-112.5 road sectors are narrower because road
///   junctions come in every angle, corridors mostly in right angles.
/// - 135 to 170: sharp (a turn back into a corridor at an acute angle).
/// - above 170: U-turn. iNavigate says "turn around" beyond 125 deg of heading error, which we use for
///   wrong-way detection (120 deg, `NavigatorOptions.wrongWayAngleDeg`), not for route geometry.
/// Boundaries belong to the larger class (exactly 45 deg is a turn; exactly 170 is sharp).
public enum TurnClassifier {
    /// |angle| below this is straight on, degrees.
    public static let straightBelowDeg = 20.0
    /// |angle| below this (and at least `straightBelowDeg`) is slight, degrees.
    public static let slightBelowDeg = 45.0
    /// |angle| below this (and at least `slightBelowDeg`) is a turn, degrees.
    public static let turnBelowDeg = 135.0
    /// |angle| up to this (and at least `turnBelowDeg`) is sharp; above is a U-turn, degrees.
    public static let sharpUpToDeg = 170.0

    /// The maneuver for a signed change of direction (degrees, positive = left); nil when straight on.
    public static func classify(signedAngleDeg a: Double) -> ManeuverKind? {
        let m = abs(a)
        if m < straightBelowDeg { return nil }
        if m > sharpUpToDeg { return .uTurn }
        let left = a > 0
        if m < slightBelowDeg { return left ? .slightLeft : .slightRight }
        if m < turnBelowDeg { return left ? .turnLeft : .turnRight }
        return left ? .sharpLeft : .sharpRight
    }
}

/// One typed step of a route.
public struct Maneuver: Sendable, Equatable {
    /// What to do.
    public var kind: ManeuverKind
    /// Where, meters in the floor's frame (the control point, door, landing or destination).
    public var position: Point2
    /// Floor of `position`.
    public var floorId: String
    /// The graph node at `position`, when there is one (doors sit on edges and have none).
    public var nodeId: String?
    /// Distance along the route from its start to this maneuver, meters (vertical rides count 0).
    public var distanceFromStartMeters: Double
    /// Distance along the route from this maneuver to the next one, meters (0 for `arrive`).
    public var distanceToNextMeters: Double
    /// Signed change of direction for turns, degrees, positive = left (see `TurnClassifier`).
    public var turnAngleDeg: Double?
    /// Destination floor of an elevator or stairs maneuver.
    public var toFloorId: String?
    /// Spoken name of `toFloorId`.
    public var toFloorName: String?
    /// Spoken label of the place: door label, node label, destination name.
    public var label: String?
    /// True when this maneuver follows the previous one so closely (less than 3 m, see
    /// `RouteBuilder.chainMeters`) after a turn or ride that it cannot get a cue of its own without the two phrases overlapping
    /// at walking speed: it is announced right after the previous cue ("Turn right now." "Then take the
    /// elevator to Floor 4.") and gets no alert or cue of its own (valhalla's "verbal multi-cue").
    public var announcedWithPrevious = false
    /// Continuous position on the route polyline: point index + fraction of the following segment.
    /// Internal bookkeeping for progress tracking.
    var polylinePosition: Double

    /// Creates a maneuver (used by tests and by the route builder).
    public init(kind: ManeuverKind, position: Point2, floorId: String, nodeId: String? = nil,
                distanceFromStartMeters: Double = 0, distanceToNextMeters: Double = 0, turnAngleDeg: Double? = nil,
                toFloorId: String? = nil, toFloorName: String? = nil, label: String? = nil) {
        self.kind = kind; self.position = position; self.floorId = floorId; self.nodeId = nodeId
        self.distanceFromStartMeters = distanceFromStartMeters; self.distanceToNextMeters = distanceToNextMeters
        self.turnAngleDeg = turnAngleDeg; self.toFloorId = toFloorId; self.toFloorName = toFloorName
        self.label = label; self.polylinePosition = 0
    }
}
