import Foundation
import Localizer
import Navigation
import SessionFormat

/// The live set of ARKit plane anchors the pipeline scores against the walls, kept from `PlaneRecord` events
/// (replayed from planes.jsonl or forwarded by the phone's ARSession delegate). Vertical planes only; every
/// anchor is dropped when VIO resets (tracking unavailable, relocalizing or initializing again), because an
/// anchor placed in the old world frame is not valid in the new one until ARKit updates it.
///
/// Anchors also belong to the floor they were seen on: ARKit keeps an anchor after the traveler rides an
/// elevator or takes the stairs (and VIO often jumps during the ride), so a wall seen by the floor-4 elevator
/// door would otherwise be scored against floor 3's walls over and over while the traveler waits there. Each
/// anchor remembers the barometric altitude at its last add or update; it is not scored while the altitude now
/// differs from that by more than `maxAltitudeChangeMeters` (half a storey: floors are at least 3 m apart, and
/// the barometer's noise is a few decimetres). Without barometer readings nothing is held back.
struct PlaneAnchorTable {
    /// An anchor whose last add/update was at an altitude more than this from the current one is on another
    /// floor and is not scored, meters.
    static let maxAltitudeChangeMeters = 1.5
    private(set) var anchors: [String: PlaneRecord] = [:]
    /// Barometric altitude (meters, relative to the session start) at each anchor's last add/update, when known.
    private var altitudeAtUpdate: [String: Double] = [:]
    /// The latest finite barometric altitude, meters (nil before the first reading).
    private(set) var altitudeMeters: Double?
    /// True while the last frame was in a VIO reset state.
    private(set) var inReset = false

    /// Applies one event (ignored while VIO is resetting, and for horizontal planes).
    mutating func apply(_ r: PlaneRecord) {
        guard r.alignment == .vertical else { return }
        switch r.event {
        case .add, .update:
            guard !inReset else { return }
            anchors[r.anchorId] = r
            altitudeAtUpdate[r.anchorId] = altitudeMeters
        case .remove:
            anchors[r.anchorId] = nil
            altitudeAtUpdate[r.anchorId] = nil
        }
    }

    /// Takes the frame's barometric altitude (relative to the session start, meters; non-finite ignored).
    mutating func observe(altitudeMeters a: Double?) {
        if let a, a.isFinite { altitudeMeters = a }
    }

    /// Follows the frame's tracking state: a reset state empties the table.
    mutating func observe(tracking: TrackingState, reason: TrackingReason?) {
        inReset = isVIOResetState(tracking, reason)
        if inReset { anchors.removeAll(); altitudeAtUpdate.removeAll() }
    }

    /// True when the anchor was last seen on the current floor (or the altitude of either is unknown).
    private func isOnCurrentFloor(_ anchorId: String) -> Bool {
        guard let now = altitudeMeters, let then = altitudeAtUpdate[anchorId] else { return true }
        return abs(now - then) <= Self.maxAltitudeChangeMeters
    }

    /// The anchors of the current floor as localizer observations, sorted by anchor id (deterministic order).
    var observations: [PlaneObservation] {
        anchors.keys.sorted().filter(isOnCurrentFloor).compactMap { anchors[$0].flatMap(PlaneConversion.observation(of:)) }
    }
}

/// Converts ARKit plane anchors to plane records (for the phone's adapter, App/iOS/Sensors, which hands over
/// plain numbers so the arithmetic is tested on Linux) and plane records to the localizer's plane observations
/// (VIO floor plane, see `CameraPose`).
public enum PlaneConversion {
    /// The record of one ARPlaneAnchor event at frame time `t`, from the anchor's fields:
    /// `transformColumns` the anchor-to-world transform as 4 columns of 4 (simd order), `centerLocal` the
    /// plane center in anchor coordinates (ARPlaneAnchor.center), `extentWidth` / `extentHeight` and
    /// `rotationOnYAxisRad` from ARPlaneAnchor.planeExtent (width along the anchor's x axis turned by the
    /// rotation about its y axis, height along the turned z axis). The plane's normal is the anchor's +y
    /// axis; its horizontal extent sums the horizontal parts of the two extent axes (the vertical ones give
    /// the height). Nil when a number is not finite or the transform is degenerate (nothing is forwarded).
    public static func record(t: Double, anchorId: String, event: PlaneEvent, vertical: Bool, transformColumns: [[Float]],
                              centerLocal: [Float], extentWidth: Float, extentHeight: Float, rotationOnYAxisRad: Float,
                              classification: String?) -> PlaneRecord? {
        if event == .remove {
            return PlaneRecord(t: t, anchorId: anchorId, event: .remove, alignment: vertical ? .vertical : .horizontal)
        }
        guard t.isFinite, transformColumns.count == 4, transformColumns.allSatisfy({ $0.count == 4 }), centerLocal.count == 3
        else { return nil }
        let m = transformColumns.map { $0.map(Double.init) }
        let c = centerLocal.map(Double.init)
        guard m.allSatisfy({ $0.allSatisfy(\.isFinite) }), c.allSatisfy(\.isFinite), extentWidth.isFinite,
              extentHeight.isFinite, rotationOnYAxisRad.isFinite else { return nil }
        func axis(_ j: Int) -> [Double] { [m[j][0], m[j][1], m[j][2]] }
        let (x, y, z) = (axis(0), axis(1), axis(2))
        let center = (0..<3).map { m[3][$0] + x[$0] * c[0] + y[$0] * c[1] + z[$0] * c[2] }
        let ny = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).squareRoot()
        guard ny > 1e-6 else { return nil }
        let normal = y.map { $0 / ny }
        let r = Double(rotationOnYAxisRad)
        let xr = (0..<3).map { cos(r) * x[$0] - sin(r) * z[$0] }
        let zr = (0..<3).map { sin(r) * x[$0] + cos(r) * z[$0] }
        let w = Double(max(0, extentWidth)), h = Double(max(0, extentHeight))
        let horizontal = w * hypot(xr[0], xr[2]) + h * hypot(zr[0], zr[2])
        let verticalExtent = w * abs(xr[1]) + h * abs(zr[1])
        return PlaneRecord(t: t, anchorId: anchorId, event: event, alignment: vertical ? .vertical : .horizontal,
                           centerInWorld: center, normalInWorld: normal, widthMeters: horizontal, heightMeters: verticalExtent,
                           classification: classification)
    }

    /// The planes as walls in the traveler's frame at `pose` (x forward along the camera's VIO-plane yaw, y left;
    /// `PerceivedWall`), for the guidance while unsure. Planes with a non-finite number or no width are left out.
    static func perceivedWalls(_ planes: [PlaneObservation], at pose: CameraPose) -> [PerceivedWall] {
        let p = pose.positionInVIOPlane, yaw = pose.yawInVIOPlaneRad
        return planes.compactMap {
            PerceivedWall(planeCenterEast: $0.centerEast, planeCenterNorth: $0.centerNorth, planeNormalYawRad: $0.normalYawRad,
                          widthMeters: $0.widthMeters, cameraEast: p.east, cameraNorth: p.north, cameraYawRad: yaw)
        }
    }

    /// The observation of an add/update record: center and normal projected on the VIO plane, width as
    /// recorded; nil for remove events or records without a horizontal normal.
    static func observation(of r: PlaneRecord) -> PlaneObservation? {
        guard r.event != .remove, let c = r.centerInVIOPlane, let yaw = r.normalYawInVIOPlaneRad,
              let width = r.widthMeters else { return nil }
        return PlaneObservation(anchorId: PlaneObservation.anchorId(for: r.anchorId), centerEast: c.east, centerNorth: c.north,
                                normalYawRad: yaw, widthMeters: width)
    }
}
