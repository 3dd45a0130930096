// Recorded-session bundle v1: record types. A bundle is a directory holding session.json, frames.jsonl,
// optional images/, observations.jsonl, truth.jsonl and expected.jsonl. JSON Schemas: docs/schemas/.
// Reading: BundleReader.swift; writing: BundleWriter.swift. One reader and one writer serve the iOS
// recorder, the simulator and replay.

/// Version of the bundle format this code reads and writes.
public let sessionFormatVersion = 1

/// Pinhole intrinsics of the captured image, pixels. u to the right along the image's long side, v down
/// (ARKit's captured-image convention, see docs/frames.md).
public struct CameraIntrinsics: Codable, Hashable, Sendable {
    /// Focal length along u, pixels.
    public var fx: Double
    /// Focal length along v, pixels.
    public var fy: Double
    /// Principal point u, pixels.
    public var cx: Double
    /// Principal point v, pixels.
    public var cy: Double
    /// Image width, pixels.
    public var width: Int
    /// Image height, pixels.
    public var height: Int
    /// Creates intrinsics.
    public init(fx: Double, fy: Double, cx: Double, cy: Double, width: Int, height: Int) {
        self.fx = fx; self.fy = fy; self.cx = cx; self.cy = cy; self.width = width; self.height = height
    }
    /// iPhone 8 back camera at 1920 x 1440 (fx = fy = 1602, centred): the default of simulated walks.
    public static let iPhone8Full = CameraIntrinsics(fx: 1602, fy: 1602, cx: 960, cy: 720, width: 1920, height: 1440)
}

/// ARKit's tracking state.
public enum TrackingState: String, Codable, Sendable {
    /// Tracking is good.
    case normal
    /// Tracking works with reduced quality (see `TrackingReason`).
    case limited
    /// No tracking.
    case notAvailable
}

/// ARKit's reason for `limited` tracking.
public enum TrackingReason: String, Codable, Sendable {
    /// The session is starting.
    case initializing
    /// The device moves too fast.
    case excessiveMotion
    /// Too little texture or light.
    case insufficientFeatures
    /// ARKit is relocalizing after an interruption (the world origin may jump afterwards).
    case relocalizing
}

/// One camera frame's pose and metadata: a line of frames.jsonl.
public struct FrameRecord: Codable, Hashable, Sendable {
    /// Timestamp, seconds (monotonic, any origin).
    public var t: Double
    /// ARKit camera-to-world transform: 16 numbers in column-major order (as simd stores it), meters,
    /// world gravity-aligned with y up; the translation is elements 12, 13, 14.
    public var cameraToWorld: [Double]
    /// Tracking state.
    public var tracking: TrackingState
    /// Reason when tracking is limited.
    public var trackingReason: TrackingReason?
    /// Intrinsics of this frame's image.
    public var intrinsics: CameraIntrinsics
    /// Barometric altitude relative to the session start, meters (CMAltimeter).
    public var relativeAltitudeMeters: Double?
    /// Compass heading, degrees clockwise from magnetic north (Core Location), if available.
    public var compassHeadingDeg: Double?
    /// Core Location's heading accuracy for that reading (`CLHeading.headingAccuracy`: the largest expected
    /// deviation), degrees in [0, 180]; nil when unknown (older bundles, or a negative = invalid reading).
    public var compassAccuracyDeg: Double?
    /// Image file name under images/, if this frame's image was recorded.
    public var image: String?
    /// Sign kinds the recording's detector did not look for on this frame (added 2026-12): the phone's detector
    /// searches its wall kinds (pictograms, placards) in turn, a few per frame, so a frame that recorded no
    /// sighting of such a kind says nothing about it. Only on frames whose observations were recorded by a
    /// detector (the simulator writes it); nil (absent) = every kind was searched, as in older bundles.
    public var unsearchedSignKinds: [String]?

    /// Creates a frame record.
    public init(t: Double, cameraToWorld: [Double], tracking: TrackingState = .normal, trackingReason: TrackingReason? = nil,
                intrinsics: CameraIntrinsics, relativeAltitudeMeters: Double? = nil, compassHeadingDeg: Double? = nil,
                image: String? = nil, compassAccuracyDeg: Double? = nil, unsearchedSignKinds: [String]? = nil) {
        self.t = t; self.cameraToWorld = cameraToWorld; self.tracking = tracking; self.trackingReason = trackingReason
        self.intrinsics = intrinsics; self.relativeAltitudeMeters = relativeAltitudeMeters
        self.compassHeadingDeg = compassHeadingDeg; self.image = image
        self.compassAccuracyDeg = compassAccuracyDeg
        self.unsearchedSignKinds = unsearchedSignKinds
    }
}

/// One sign sighting already measured: a line of observations.jsonl.
public struct ObservationRecord: Codable, Hashable, Sendable {
    /// Timestamp of the frame it was seen in, seconds.
    public var t: Double
    /// Sign kind (`exit`, ...), or `landmark` for generic sightings imported from other apps.
    public var kind: String
    /// Horizontal range from the camera to the sign, meters.
    public var rangeMeters: Double
    /// Horizontal bearing of the sign from the camera's forward direction, radians, positive to the left
    /// (counter-clockwise seen from above).
    public var bearingRad: Double
    /// Detector confidence 0...1.
    public var score: Double
    /// Where it came from: `simulated`, `cascade`, `unet`, `imported`.
    public var source: String?
    /// For imported generic landmarks: the landmark's id in the source data.
    public var landmarkId: String?
    /// The legend read on the sign when it identifies one (a room-number placard's "402", as text recognition
    /// read it); absent when not read. Matched to the map sign of this kind with this text.
    public var text: String?
    /// Creates an observation record.
    public init(t: Double, kind: String, rangeMeters: Double, bearingRad: Double, score: Double, source: String? = nil,
                landmarkId: String? = nil, text: String? = nil) {
        self.t = t; self.kind = kind; self.rangeMeters = rangeMeters; self.bearingRad = bearingRad; self.score = score
        self.source = source; self.landmarkId = landmarkId; self.text = text
    }
}

/// Ground truth of a simulated or surveyed walk: a line of truth.jsonl.
public struct TruthRecord: Codable, Hashable, Sendable {
    /// Timestamp, seconds (same clock as frames).
    public var t: Double
    /// Map x, meters.
    public var x: Double
    /// Map y, meters.
    public var y: Double
    /// Floor id.
    public var floorId: String
    /// Heading of the camera's forward direction in the map frame, radians CCW from +x.
    public var headingRad: Double
    /// Creates a truth record.
    public init(t: Double, x: Double, y: Double, floorId: String, headingRad: Double) {
        self.t = t; self.x = x; self.y = y; self.floorId = floorId; self.headingRad = headingRad
    }
}

/// An announcement a replay must produce: a line of expected.jsonl.
public struct ExpectedAnnouncement: Codable, Hashable, Sendable {
    /// The spoken text, exactly.
    public var text: String
    /// Earliest time it may be spoken, seconds (nil: any time).
    public var notBefore: Double?
    /// Latest time it may be spoken, seconds (nil: any time).
    public var notAfter: Double?
    /// Creates an expected announcement.
    public init(text: String, notBefore: Double? = nil, notAfter: Double? = nil) {
        self.text = text; self.notBefore = notBefore; self.notAfter = notAfter
    }
}

/// session.json: what the whole recording is.
public struct SessionInfo: Codable, Hashable, Sendable {
    /// Bundle format version (1).
    public var formatVersion: Int
    /// Recording device ("iPhone12,1", "simulator").
    public var device: String
    /// Version of the app or tool that wrote it.
    public var appVersion: String
    /// Id of the building map it was recorded in, if known.
    public var mapId: String?
    /// Floor id at the start, if known.
    public var floorId: String?
    /// Start point-of-interest id, if the traveler chose one.
    public var start: String?
    /// Destination point-of-interest id, if chosen.
    public var destination: String?
    /// Physical height of the signs' face used for ranging, meters.
    public var signHeightMeters: Double
    /// Default intrinsics of the frames.
    public var intrinsics: CameraIntrinsics?
    /// How the phone was carried: `handheld` or `lanyard`.
    public var carry: String?
    /// Where the recording came from when it was not recorded by Wayfinder itself (an imported file, with
    /// its original identifiers), free text; nil for Wayfinder's own recordings and simulations.
    public var source: String?
    /// Creates session info.
    public init(formatVersion: Int = sessionFormatVersion, device: String, appVersion: String, mapId: String? = nil,
                floorId: String? = nil, start: String? = nil, destination: String? = nil, signHeightMeters: Double = 0.21,
                intrinsics: CameraIntrinsics? = nil, carry: String? = nil, source: String? = nil) {
        self.formatVersion = formatVersion; self.device = device; self.appVersion = appVersion; self.mapId = mapId
        self.floorId = floorId; self.start = start; self.destination = destination; self.signHeightMeters = signHeightMeters
        self.intrinsics = intrinsics; self.carry = carry; self.source = source
    }
}
