import Foundation
import Maps
import SessionFormat

/// The truth behind one simulated observation (diagnostics; parallel to the walk's observations).
public struct ObservationTruth: Sendable, Codable, Equatable {
    /// The sign seen; nil for a false positive.
    public var signId: String?
    /// True horizontal range, meters (nil for a false positive).
    public var trueRangeMeters: Double?
    /// True bearing, radians, positive left (nil for a false positive).
    public var trueBearingRad: Double?
    /// The look-alike seen, for a false positive that is one (`DetectorParameters.lookAlikesPerMeterOfWall`);
    /// nil for a sign and for a one-frame false positive.
    public var lookAlikeId: String? = nil
}

/// A sign that was truly visible on a processed frame, detected or missed (diagnostics for detection rates).
public struct VisibleSign: Sendable, Codable, Equatable {
    /// Frame index.
    public var frameIndex: Int
    /// Sign id.
    public var signId: String
    /// True horizontal range, meters.
    public var rangeMeters: Double
    /// Whether the simulated detector reported it.
    public var detected: Bool
    /// Whether motion blur (a fast turn) halved the detection probability.
    public var blurred: Bool
}

/// The Exit-sign detector and range estimator as seen by the localizer: on every processed frame, each truly
/// visible sign (in the image with a small margin for the actual pitch and roll, within the detector's range,
/// its face towards the camera unless double-sided, no wall in between) is detected with a probability that
/// falls with range (halved during fast turns: motion blur); a detection reports the range with log-normal
/// noise and the bearing with normal noise. False positives arrive as a Bernoulli process per processed frame
/// with uniform range and a bearing inside the field of view.
struct SignObservationModel {
    let parameters: DetectorParameters
    let floors: [String: Floor]
    let geometry: [String: FloorGeometry]
    /// Intrinsics used for the visibility test (the field of view only depends on their ratios).
    let intrinsics: CameraIntrinsics
    /// The building's sign kinds: a kind's own recognition range and view angle (`SignKindSpec`) cap the
    /// detector's, and its detection-probability curve is shrunk to that range (a placard read from 2.5 m).
    let catalogue: SignCatalogue
    /// Default mounting height of a sign's bottom edge when the map has none, meters.
    static let defaultMountingHeightMeters = 2.3
    /// Text recognition on a detected sign with an identifying legend (`Sign.text`): read right with this
    /// probability, misread as another legend of its kind on the floor with `textMisreadProbability`, else not
    /// read (the sighting carries no text). The share of room-number reads iOS's text recognizer gets right on
    /// a placard seen square on within its range is a guess (no field data here); misreads of one digit are
    /// the dangerous case and are kept in so the localizer's clutter share is exercised.
    static let textReadProbability = 0.8
    static let textMisreadProbability = 0.03
    /// Look-alikes by floor id (`DetectorParameters.lookAlikesPerMeterOfWall`; `placeLookAlikes`): pseudo-signs of
    /// the floor's false-positive kind. Empty by default.
    var lookAlikes: [String: [Sign]] = [:]
    /// The survey's size errors (`SurveyErrors.rangeFactors`, by floor id then sign id): each sign's ranges read
    /// with its factor (`floors` are then the survey's true floors). Empty: the map's sizes are the truth.
    var surveyRangeFactors: [String: [String: Double]] = [:]

    /// Places the look-alikes of every floor (`DetectorParameters.lookAlikesPerMeterOfWall`), of the floor's
    /// `falsePositiveKind`: on each floor round(density x total wall length) of them, each on a wall drawn with
    /// probability proportional to its length, at a uniform point along it, on a side drawn at random, 5 cm off the
    /// wall and facing away from it. Deterministic for `rng`; floors in id order.
    func placeLookAlikes(rng: inout SeededRandom) -> [String: [Sign]] {
        guard parameters.lookAlikesPerMeterOfWall > 0 else { return [:] }
        var out: [String: [Sign]] = [:]
        for floorId in floors.keys.sorted() {
            guard let walls = geometry[floorId]?.walls, !walls.isEmpty else { continue }
            let lengths = walls.map { hypot($0.to.x - $0.from.x, $0.to.y - $0.from.y) }
            let total = lengths.reduce(0, +)
            let count = Int((parameters.lookAlikesPerMeterOfWall * total).rounded())
            guard total > 0, count > 0 else { continue }
            var cumulative: [Double] = []
            var sum = 0.0
            for l in lengths { sum += l; cumulative.append(sum) }
            var placed: [Sign] = []
            for i in 0..<count {
                let pick = rng.uniform() * total, along = rng.uniform(), side = rng.uniform() < 0.5 ? -1.0 : 1.0
                let w = min(cumulative.firstIndex { $0 >= pick } ?? walls.count - 1, walls.count - 1)
                let wall = walls[w], length = lengths[w]
                guard length > 1e-6 else { continue }
                let ux = (wall.to.x - wall.from.x) / length, uy = (wall.to.y - wall.from.y) / length
                let nx = -uy * side, ny = ux * side
                let x = wall.from.x + along * (wall.to.x - wall.from.x) + 0.05 * nx
                let y = wall.from.y + along * (wall.to.y - wall.from.y) + 0.05 * ny
                placed.append(Sign(id: "look-alike-\(floorId)-\(i)", kind: falsePositiveKind(onFloor: floorId), position: Point2(x, y),
                                   facing: Point2(nx, ny), widthMeters: 0.3, heightMeters: 0.15))
            }
            out[floorId] = placed
        }
        return out
    }

    /// Recognition range of `sign`, meters: its kind's own (`SignKindSpec.maxRangeMeters`) capped by the
    /// detector's.
    func maxRangeMeters(of sign: Sign) -> Double {
        min(parameters.maxRangeMeters, catalogue.spec(kind: sign.kind)?.maxRangeMeters ?? .infinity)
    }

    /// Largest view angle from the face normal at which `sign` is recognised, degrees (its kind's, capped by
    /// the detector's).
    func maxViewAngleDeg(of sign: Sign) -> Double {
        min(parameters.maxViewAngleFromNormalDeg, catalogue.spec(kind: sign.kind)?.maxViewAngleDeg ?? .infinity)
    }

    /// Pixel of a map-frame 3D point (x east, y north, z up) for a camera pose expressed with the map as the
    /// world (world x = map x, world y = up, world z = -map y); nil when behind the camera.
    static func project(_ point: (x: Double, y: Double, z: Double), pose: CameraPose, intrinsics k: CameraIntrinsics) -> (u: Double, v: Double)? {
        let m = pose.columnMajor
        let d = (point.x - m[12], point.z - m[13], -point.y - m[14])
        let cx = m[0] * d.0 + m[1] * d.1 + m[2] * d.2
        let cy = m[4] * d.0 + m[5] * d.1 + m[6] * d.2
        let cz = m[8] * d.0 + m[9] * d.1 + m[10] * d.2
        guard cz < -1e-6 else { return nil }
        return (k.cx + k.fx * cx / -cz, k.cy - k.fy * cy / -cz)
    }

    /// The camera pose with the map as world (see `project`).
    static func mapPose(_ s: TrueCameraState) -> CameraPose {
        CameraPose(positionInWorld: (x: s.position.x, y: s.heightAboveFloorMeters, z: -s.position.y),
                   yawRad: s.yawRad, pitchRad: s.pitchRad, rollRad: s.rollRad)
    }

    /// Signs truly visible from `s`: (sign, range, bearing).
    func visibleSigns(from s: TrueCameraState) -> [(sign: Sign, rangeMeters: Double, bearingRad: Double)] {
        visible(floors[s.floorId]?.signs ?? [], from: s)
    }

    /// Which of `signs` (on the floor of `s`) are truly visible from `s`: (sign, range, bearing).
    func visible(_ signs: [Sign], from s: TrueCameraState) -> [(sign: Sign, rangeMeters: Double, bearingRad: Double)] {
        guard !signs.isEmpty, let geo = geometry[s.floorId] else { return [] }
        let pose = Self.mapPose(s)
        let k = intrinsics
        let mu = parameters.imageMargin * Double(k.width) / 2, mv = parameters.imageMargin * Double(k.height) / 2
        var out: [(Sign, Double, Double)] = []
        for sign in signs {
            let dx = sign.position.x - s.position.x, dy = sign.position.y - s.position.y
            let r = hypot(dx, dy)
            guard r >= parameters.minRangeMeters, r <= maxRangeMeters(of: sign) else { continue }
            guard sign.faceIsTurned(towardsViewerAtOffset: dx, dy, distanceMeters: r,
                                    maxViewAngleDeg: maxViewAngleDeg(of: sign)) else { continue }
            let mount = sign.mountingHeightMeters ?? Self.defaultMountingHeightMeters
            guard let px = Self.project((sign.position.x, sign.position.y, mount + sign.heightMeters / 2), pose: pose, intrinsics: k),
                  px.u >= mu, px.u <= Double(k.width) - mu, px.v >= mv, px.v <= Double(k.height) - mv else { continue }
            if geo.segmentCrossesWall(s.position.asPoint, sign.lineOfSightEnd(viewerOffset: dx, dy, distanceMeters: r)) { continue }
            out.append((sign, r, wrapAngle(atan2(dy, dx) - s.yawRad)))
        }
        return out
    }

    /// The kind a false positive on floor `floorId` is reported as: an Exit sign when the floor has any (the
    /// rates come from the Exit detector on real photos: posters, red ceiling lights, markers taken for Exit
    /// signs, issue 16), else the kind of the floor's first sign. Before the twenty-third stop it was always the
    /// floor's first sign's kind: a placard on both of the bundled office's floors, whose false sightings at 1-12 m
    /// no hypothesis could explain (placards are recognised to 2.5 m), so the office walks never met a false
    /// Exit sighting.
    func falsePositiveKind(onFloor floorId: String) -> String {
        guard let signs = floors[floorId]?.signs else { return "exit" }
        if signs.contains(where: { $0.kind == "exit" }) { return "exit" }
        return signs.first?.kind ?? "exit"
    }

    /// A detection's measured range and bearing: the true ones with the detector's range bias, log-normal range
    /// noise (`zRange` a standard normal draw) and normal bearing noise (`zBearing`).
    private func measured(rangeMeters r: Double, bearingRad b: Double, zRange: Double, zBearing: Double)
        -> (rangeMeters: Double, bearingRad: Double) {
        (r * (1 + parameters.rangeBias) * exp(parameters.rangeLogSigma * zRange),
         wrapAngle(b + radians(parameters.bearingSigmaDeg) * zBearing))
    }

    /// A false positive's score: `drawn` (uniform 0.3-0.7) when the scores tell false positives apart, else the
    /// constant score every observation gets.
    private func falsePositiveScore(drawn: Double) -> Double {
        parameters.scoresTellFalsePositives ? drawn : parameters.constantScore
    }

    /// Observations of one processed frame.
    /// `lookAlikeRng` draws the look-alikes' detections (untouched when the floor has none, so walks without
    /// look-alikes are the same as before them).
    func observe(frameIndex: Int, state s: TrueCameraState, rng: inout SeededRandom, fpRng: inout SeededRandom,
                 lookAlikeRng: inout SeededRandom,
                 visibleLog: inout [VisibleSign]) -> [(ObservationRecord, ObservationTruth)] {
        let p = parameters
        var out: [(ObservationRecord, ObservationTruth)] = []
        let blur = abs(s.yawRateRadPerSecond) > radians(p.motionBlurTurnRateDegPerSecond) ? 0.5 : 1.0
        for (sign, r, b) in visibleSigns(from: s) {
            // A kind recognised from closer has the detector's curve shrunk to its range.
            let pd = p.detectionProbability(rangeMeters: r * p.maxRangeMeters / maxRangeMeters(of: sign)) * blur
            // Draw all three numbers whether detected or not, so streams stay aligned.
            let u = rng.uniform(), zr = rng.normal(), zb = rng.normal(), zs = rng.normal()
            let detected = u < pd
            visibleLog.append(VisibleSign(frameIndex: frameIndex, signId: sign.id, rangeMeters: r, detected: detected, blurred: blur < 1))
            guard detected else { continue }
            let (measuredRange, bearing) = measured(rangeMeters: r, bearingRad: b, zRange: zr, zBearing: zb)
            // A face larger than the catalogue's reads nearer (the range comes from its apparent height).
            let range = measuredRange * (surveyRangeFactors[s.floorId]?[sign.id] ?? 1)
            let score = p.scoresTellFalsePositives ? max(0.3, min(0.99, 0.92 - 0.03 * r + 0.04 * zs)) : p.constantScore
            // Text recognition, only for identifying legends (so the streams of maps without any are unchanged).
            var text: String? = nil
            if let legend = sign.text {
                let ut = rng.uniform(), pick = rng.uniform()
                if ut < Self.textReadProbability {
                    text = legend
                } else if ut < Self.textReadProbability + Self.textMisreadProbability {
                    let others = (floors[s.floorId]?.signs ?? []).filter { $0.kind == sign.kind && $0.text != nil && $0.text != legend }
                    if !others.isEmpty { text = others[min(others.count - 1, Int(pick * Double(others.count)))].text }
                }
            }
            out.append((ObservationRecord(t: s.t, kind: sign.kind, rangeMeters: range, bearingRad: bearing, score: score,
                                          source: "simulated", text: text),
                        ObservationTruth(signId: sign.id, trueRangeMeters: r, trueBearingRad: b)))
        }
        // Look-alikes in view: detected like an Exit sign at their range, times the look-alike share.
        for (alike, r, b) in visible(lookAlikes[s.floorId] ?? [], from: s) {
            let pd = p.detectionProbability(rangeMeters: r) * blur * p.lookAlikeDetectionShare
            let u = lookAlikeRng.uniform(), zr = lookAlikeRng.normal(), zb = lookAlikeRng.normal(), zs = lookAlikeRng.uniform(0.3, 0.7)
            guard u < pd else { continue }
            let (range, bearing) = measured(rangeMeters: r, bearingRad: b, zRange: zr, zBearing: zb)
            out.append((ObservationRecord(t: s.t, kind: alike.kind, rangeMeters: range, bearingRad: bearing,
                                          score: falsePositiveScore(drawn: zs), source: "simulated"),
                        ObservationTruth(signId: nil, trueRangeMeters: nil, trueBearingRad: nil, lookAlikeId: alike.id)))
        }
        let fpDraw = fpRng.uniform(), fr = fpRng.uniform(1, p.maxRangeMeters), fb = fpRng.uniform(-1, 1), fs = fpRng.uniform(0.3, 0.7)
        if fpDraw < p.falsePositivesPerFrame {
            let portrait = abs(sin(s.rollRad)) > abs(cos(s.rollRad))
            let halfPixels = portrait ? intrinsics.cy : intrinsics.cx
            let fx = portrait ? intrinsics.fy : intrinsics.fx
            let halfFov = atan(halfPixels / fx)
            out.append((ObservationRecord(t: s.t, kind: falsePositiveKind(onFloor: s.floorId), rangeMeters: fr,
                                          bearingRad: fb * halfFov, score: falsePositiveScore(drawn: fs), source: "simulated"),
                        ObservationTruth(signId: nil, trueRangeMeters: nil, trueBearingRad: nil)))
        }
        return out
    }
}

extension Point2Value {
    var asPoint: Point2 { Point2(x, y) }
}
