import Foundation
import Localizer
import SessionFormat

/// The live set of ARKit plane anchors the pipeline scores against the walls, kept from `PlaneRecord` events
/// (replayed from planes.jsonl or forwarded by the phone's ARSession delegate). Vertical planes only; every
/// anchor is dropped when VIO resets (tracking unavailable, relocalizing or initializing again), because an
/// anchor placed in the old world frame is not valid in the new one until ARKit updates it.
struct PlaneAnchorTable {
    private(set) var anchors: [String: PlaneRecord] = [:]
    /// True while the last frame was in a VIO reset state.
    private(set) var inReset = false

    /// Applies one event (ignored while VIO is resetting, and for horizontal planes).
    mutating func apply(_ r: PlaneRecord) {
        guard r.alignment == .vertical else { return }
        switch r.event {
        case .add, .update:
            guard !inReset else { return }
            anchors[r.anchorId] = r
        case .remove:
            anchors[r.anchorId] = nil
        }
    }

    /// Follows the frame's tracking state: a reset state empties the table.
    mutating func observe(tracking: TrackingState, reason: TrackingReason?) {
        inReset = isVIOResetState(tracking, reason)
        if inReset { anchors.removeAll() }
    }

    /// The anchors as localizer observations, sorted by anchor id (deterministic order).
    var observations: [PlaneObservation] {
        anchors.keys.sorted().compactMap { anchors[$0].flatMap(PlaneConversion.observation(of:)) }
    }
}

/// Converts plane records to the localizer's plane observations (VIO floor plane, see `CameraPose`).
enum PlaneConversion {
    /// The observation of an add/update record: center and normal projected on the VIO plane, width as
    /// recorded; nil for remove events or records without a horizontal normal.
    static func observation(of r: PlaneRecord) -> PlaneObservation? {
        guard r.event != .remove, let c = r.centerInVIOPlane, let yaw = r.normalYawInVIOPlaneRad,
              let width = r.widthMeters else { return nil }
        return PlaneObservation(anchorId: PlaneObservation.anchorId(for: r.anchorId), centerEast: c.east, centerNorth: c.north,
                                normalYawRad: yaw, widthMeters: width)
    }
}
