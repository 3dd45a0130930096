import Foundation

/// How the phone is carried.
public enum CarryMode: String, Codable, Sendable, CaseIterable {
    /// Held in the hand, camera forward (small tremor, pitch -5...20 degrees).
    case handheld
    /// Hanging on a lanyard at the chest: larger pitch, roll and yaw swings at the step frequency.
    case lanyard
}

/// How the phone's long side is held.
public enum PhoneOrientation: String, Codable, Sendable, CaseIterable {
    /// Portrait, the traveler's usual posture: ARKit roll about -90 degrees, horizontal field of view ~48 degrees.
    case portrait
    /// Landscape: roll about 0, horizontal field of view ~62 degrees.
    case landscape
}

/// One simulated walk, as committed under Tests/Scenarios/*.json and given to `WalkSimulator.simulate`.
/// Optional keys take the defaults documented on each property when absent from the JSON.
public struct SimulationScenario: Codable, Sendable, Equatable {
    /// Short unique name (also the file's base name in Tests/Scenarios).
    public var name: String
    /// What the scenario exercises, for people.
    public var description: String?
    /// Which map: `office` (the bundled two-floor office), `skeri:<floor>` (the Smith-Kettlewell floor imported
    /// from ../shared/data/skeri_inavigate), or a path to a map-v1 JSON file. Default `office`.
    public var map: String
    /// Start: a point-of-interest id or name, or a graph node id.
    public var from: String
    /// Destination: a point-of-interest id or name, or a graph node id.
    public var to: String
    /// Seed of every random draw; the same scenario and seed give the same walk byte for byte.
    public var seed: UInt64
    /// How the phone is carried. Default handheld.
    public var carry: CarryMode
    /// How the phone is held. Default portrait.
    public var orientation: PhoneOrientation
    /// True when session.json names the start place (the traveler chose it); false gives only the floor.
    /// Default false.
    public var startKnown: Bool
    /// Time (seconds from the start) at which ARKit loses tracking (`notAvailable`, pose frozen), if any.
    public var trackingLossAt: Double?
    /// Length of that tracking loss, seconds. Default 4.
    public var trackingLossDurationSeconds: Double
    /// Time (seconds) of a full VIO reset: every later pose is in a new arbitrary world frame. None by default.
    public var vioResetAt: Double?
    /// True to take a wrong branch at one junction, walk a few meters, turn around and rejoin the route.
    public var wrongTurn: Bool
    /// Camera frame rate, Hz. Default 30.
    public var rateHz: Double
    /// Rate of frames the detector processes (observations are only produced on those), Hz. Default 10.
    public var detectorRateHz: Double
    /// True to render camera images (640 x 480 PPM) for the processed frames at `imageRateHz`. Default false.
    public var images: Bool
    /// Rate of rendered images when `images` is set, Hz (rounded to a whole frame stride). Default 2.
    public var imageRateHz: Double
    /// Angle from magnetic north to the map's +y axis, degrees clockwise (what a compass reads when facing map
    /// north, before disturbance). nil takes the map's `compassHeadingOfMapNorthDeg`, or draws it from the seed
    /// when the map has none (the localizer then knows no north either).
    public var mapNorthOffsetDeg: Double?
    /// The start place the traveler tells the app (a point-of-interest id or name), when it is not where the walk
    /// really begins (`from`): session.json names it as the start, so the localizer starts from the wrong
    /// place and must recover. Implies a known start. nil (the default): session.json names `from` when
    /// `startKnown`, nothing otherwise.
    public var declaredStart: String?
    /// A long tour instead of one walk: when set, the walker goes from `from` to `to`, turns around, walks back,
    /// and so on (the route chained with its reverse, a stop and turn at each end) until at least this many
    /// minutes of walking are planned at the fastest preferred speed. For long-replay measurements
    /// (docs/localizer.md, "Speed"). nil (the default): one walk.
    public var tourMinutes: Double?

    /// Creates a scenario; every optional setting has its documented default.
    public init(name: String, description: String? = nil, map: String = "office", from: String, to: String, seed: UInt64,
                carry: CarryMode = .handheld, orientation: PhoneOrientation = .portrait, startKnown: Bool = false,
                trackingLossAt: Double? = nil, trackingLossDurationSeconds: Double = 4, vioResetAt: Double? = nil,
                wrongTurn: Bool = false, rateHz: Double = 30, detectorRateHz: Double = 10, images: Bool = false,
                imageRateHz: Double = 2, mapNorthOffsetDeg: Double? = nil, declaredStart: String? = nil,
                tourMinutes: Double? = nil) {
        self.name = name; self.description = description; self.map = map; self.from = from; self.to = to; self.seed = seed
        self.carry = carry; self.orientation = orientation; self.startKnown = startKnown
        self.trackingLossAt = trackingLossAt; self.trackingLossDurationSeconds = trackingLossDurationSeconds
        self.vioResetAt = vioResetAt; self.wrongTurn = wrongTurn; self.rateHz = rateHz; self.detectorRateHz = detectorRateHz
        self.images = images; self.imageRateHz = imageRateHz; self.mapNorthOffsetDeg = mapNorthOffsetDeg
        self.declaredStart = declaredStart
        self.tourMinutes = tourMinutes
    }

    private enum CodingKeys: String, CodingKey {
        case name, description, map, from, to, seed, carry, orientation, startKnown, trackingLossAt
        case trackingLossDurationSeconds, vioResetAt, wrongTurn, rateHz, detectorRateHz, images, imageRateHz
        case mapNorthOffsetDeg, declaredStart, tourMinutes
    }

    /// Decodes, filling absent optional keys with their defaults.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        name = try c.decode(String.self, forKey: .name)
        description = try c.decodeIfPresent(String.self, forKey: .description)
        map = try c.decodeIfPresent(String.self, forKey: .map) ?? "office"
        from = try c.decode(String.self, forKey: .from)
        to = try c.decode(String.self, forKey: .to)
        seed = try c.decode(UInt64.self, forKey: .seed)
        carry = try c.decodeIfPresent(CarryMode.self, forKey: .carry) ?? .handheld
        orientation = try c.decodeIfPresent(PhoneOrientation.self, forKey: .orientation) ?? .portrait
        startKnown = try c.decodeIfPresent(Bool.self, forKey: .startKnown) ?? false
        trackingLossAt = try c.decodeIfPresent(Double.self, forKey: .trackingLossAt)
        trackingLossDurationSeconds = try c.decodeIfPresent(Double.self, forKey: .trackingLossDurationSeconds) ?? 4
        vioResetAt = try c.decodeIfPresent(Double.self, forKey: .vioResetAt)
        wrongTurn = try c.decodeIfPresent(Bool.self, forKey: .wrongTurn) ?? false
        rateHz = try c.decodeIfPresent(Double.self, forKey: .rateHz) ?? 30
        detectorRateHz = try c.decodeIfPresent(Double.self, forKey: .detectorRateHz) ?? 10
        images = try c.decodeIfPresent(Bool.self, forKey: .images) ?? false
        imageRateHz = try c.decodeIfPresent(Double.self, forKey: .imageRateHz) ?? 2
        mapNorthOffsetDeg = try c.decodeIfPresent(Double.self, forKey: .mapNorthOffsetDeg)
        declaredStart = try c.decodeIfPresent(String.self, forKey: .declaredStart)
        tourMinutes = try c.decodeIfPresent(Double.self, forKey: .tourMinutes)
    }

    /// Checks the settings' ranges; throws `SimulationError.invalidScenario` naming the first bad one.
    public func validate() throws {
        func bad(_ s: String) -> SimulationError { .invalidScenario("\(name): \(s)") }
        guard rateHz.isFinite, rateHz >= 1, rateHz <= 240 else { throw bad("rateHz must be in 1...240, got \(rateHz)") }
        guard detectorRateHz.isFinite, detectorRateHz > 0 else { throw bad("detectorRateHz must be positive") }
        guard imageRateHz.isFinite, imageRateHz > 0 else { throw bad("imageRateHz must be positive") }
        if let t = trackingLossAt, !(t.isFinite && t >= 0) { throw bad("trackingLossAt must be >= 0") }
        guard trackingLossDurationSeconds.isFinite, trackingLossDurationSeconds > 0, trackingLossDurationSeconds < 120 else {
            throw bad("trackingLossDurationSeconds must be in (0, 120)")
        }
        if let t = vioResetAt, !(t.isFinite && t >= 0) { throw bad("vioResetAt must be >= 0") }
        if let n = mapNorthOffsetDeg, !n.isFinite { throw bad("mapNorthOffsetDeg must be finite") }
        guard !from.isEmpty, !to.isEmpty else { throw bad("from and to must be non-empty") }
        if let d = declaredStart, d.isEmpty { throw bad("declaredStart must be non-empty when given") }
        if let m = tourMinutes {
            guard m.isFinite, m > 0, m <= 180 else { throw bad("tourMinutes must be in (0, 180], got \(m)") }
            guard !wrongTurn else { throw bad("tourMinutes cannot be combined with wrongTurn") }
        }
    }

    /// Loads a scenario file (JSON); errors name the file.
    public static func load(contentsOf url: URL) throws -> SimulationScenario {
        let data: Data
        do { data = try Data(contentsOf: url) } catch {
            throw SimulationError.invalidScenario("cannot read \(url.path): \(error.localizedDescription)")
        }
        do {
            let s = try JSONDecoder().decode(SimulationScenario.self, from: data)
            try s.validate()
            return s
        } catch let e as SimulationError {
            throw e
        } catch {
            throw SimulationError.invalidScenario("\(url.lastPathComponent): \(error)")
        }
    }
}
