import Foundation
import Localizer
import Maps

/// The sign kinds the localizer's hypotheses expect in view: for each kind, the summed weight of the hypotheses
/// (`LocalizationEstimate.hypotheses`: clusters of at least 1 % of the weight) from whose pose some sign of that kind
/// is in view: within the kind's recognition range (`SignKindSpec.maxRangeMeters`, capped by the detector's
/// `maxRangeMeters`) and at least 0.5 m away, inside the camera's horizontal field of view, its face turned towards
/// the camera within the kind's view angle (either face of a double-sided sign), and no wall of the map in between.
/// The same geometry as the simulator's detector model (`Sign.faceIsTurned`, `lineOfSightEnd`), without the image
/// margins. Feeds `WallKindScheduler`.
public enum ExpectedSignKinds {
    /// Weight share by kind, for the kinds in `kinds` (absent: no hypothesis expects it). `halfFieldOfViewRad`: half
    /// the camera's horizontal field of view, radians; `maxRangeMeters`: the detector's farthest range.
    public static func shares(hypotheses: [PoseHypothesis], building: Building, kinds: Set<String>,
                              halfFieldOfViewRad: Double, maxRangeMeters: Double) -> [String: Double] {
        guard !kinds.isEmpty else { return [:] }
        var shares: [String: Double] = [:]
        for h in hypotheses where h.weight > 0 {
            guard let floor = building.floor(id: h.floorId) else { continue }
            var seen = Set<String>()
            for sign in floor.signs where kinds.contains(sign.kind) && !seen.contains(sign.kind) {
                if inView(sign, from: h.positionInMap, headingRad: h.headingRad, floor: floor, building: building,
                          halfFieldOfViewRad: halfFieldOfViewRad, maxRangeMeters: maxRangeMeters) {
                    seen.insert(sign.kind)
                }
            }
            for kind in seen { shares[kind, default: 0] += h.weight }
        }
        return shares
    }

    /// Whether `sign` is in view of a camera at `p` facing `headingRad` (radians CCW from map +x) on `floor`.
    static func inView(_ sign: Sign, from p: Point2, headingRad: Double, floor: Floor, building: Building,
                       halfFieldOfViewRad: Double, maxRangeMeters: Double) -> Bool {
        let spec = building.signCatalogue.spec(kind: sign.kind)
        let dx = sign.position.x - p.x, dy = sign.position.y - p.y
        let r = hypot(dx, dy)
        guard r >= 0.5, r <= min(maxRangeMeters, spec?.maxRangeMeters ?? .infinity) else { return false }
        guard abs(remainder(atan2(dy, dx) - headingRad, 2 * Double.pi)) <= halfFieldOfViewRad else { return false }
        guard sign.faceIsTurned(towardsViewerAtOffset: dx, dy, distanceMeters: r,
                                maxViewAngleDeg: spec?.maxViewAngleDeg ?? SignKindSpec.detectorMaxViewAngleDeg) else { return false }
        return !floor.crossesWall(from: p, to: sign.lineOfSightEnd(viewerOffset: dx, dy, distanceMeters: r))
    }
}
