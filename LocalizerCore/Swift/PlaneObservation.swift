internal import LocalizerCore

/// One vertical plane (an ARKit ARPlaneAnchor with alignment vertical) on the VIO floor plane, in the same
/// frame as `VIOSample` poses: what `ParticleLocalizer.updatePlanes` scores against the map's walls.
public struct PlaneObservation: Sendable, Hashable {
    /// Stable id of the anchor (`PlaneObservation.anchorId(for:)` of its UUID string): the filter applies each
    /// anchor at most once per short interval.
    public var anchorId: UInt64
    /// Plane center on the VIO plane, meters (east = x_w, north = -z_w of the ARKit world).
    public var centerEast: Double
    /// See `centerEast`.
    public var centerNorth: Double
    /// Direction of the plane's normal on the VIO plane, radians CCW from VIO east (either side).
    public var normalYawRad: Double
    /// Horizontal extent along the wall, meters (narrow or zero-width planes are ignored by the filter).
    public var widthMeters: Double

    /// Creates an observation.
    public init(anchorId: UInt64, centerEast: Double, centerNorth: Double, normalYawRad: Double, widthMeters: Double) {
        self.anchorId = anchorId; self.centerEast = centerEast; self.centerNorth = centerNorth
        self.normalYawRad = normalYawRad; self.widthMeters = widthMeters
    }

    /// A stable 64-bit id for an anchor identifier string (FNV-1a over its UTF-8 bytes; the same on every
    /// run and platform, unlike `Hasher`).
    public static func anchorId(for identifier: String) -> UInt64 {
        var h: UInt64 = 0xcbf2_9ce4_8422_2325
        for b in identifier.utf8 { h = (h ^ UInt64(b)) &* 0x0000_0100_0000_01b3 }
        return h
    }
}

extension LocalizerBridge.Handle {
    /// wf_localizer_update_planes over `planes` at time `t`.
    func updatePlanes(_ planes: [PlaneObservation], t: Double) throws {
        let obs = planes.map {
            wf_plane_observation(anchor_id: $0.anchorId, center_east_m: $0.centerEast, center_north_m: $0.centerNorth,
                                 normal_yaw_rad: $0.normalYawRad, width_m: $0.widthMeters)
        }
        let status = obs.withUnsafeBufferPointer { wf_localizer_update_planes(raw, $0.baseAddress, $0.count, t) }
        guard status != WF_LOC_OK.rawValue else { return }
        throw LocalizerBridge.error(status, message: String(cString: wf_localizer_last_error(raw)))
    }
}
