internal import LocalizerCore
import Maps

// Every call into the C particle-filter ABI (LocalizerCore/include/wf_localizer.h) goes through this file;
// the public Swift API (ParticleLocalizer.swift, LocalizerTypes.swift) never shows a C type. Status codes
// become LocalizerError with the handle's last error message.

enum LocalizerBridge {
    /// Owns one wf_localizer handle; frees it in deinit.
    final class Handle {
        let raw: OpaquePointer

        init(raw: OpaquePointer) { self.raw = raw }
        deinit { wf_localizer_free(raw) }

        private func check(_ status: Int32) throws {
            guard status != WF_LOC_OK.rawValue else { return }
            throw LocalizerBridge.error(status, message: String(cString: wf_localizer_last_error(raw)))
        }

        func initFloorOnly(floor: Int32) throws { try check(wf_localizer_init_floor_only(raw, floor)) }

        func initStartPoint(floor: Int32, x: Double, y: Double, radiusMeters: Double) throws {
            try check(wf_localizer_init_start_point(raw, floor, x, y, radiusMeters))
        }

        func setCompassPrior(headingInMapRad: Double, sigmaRad: Double) throws {
            try check(wf_localizer_set_compass_prior(raw, headingInMapRad, sigmaRad))
        }

        func predict(_ s: VIOSample) throws {
            let tracking: wf_vio_tracking
            switch s.tracking {
            case .normal: tracking = WF_VIO_TRACKING_NORMAL
            case .limited: tracking = WF_VIO_TRACKING_LIMITED
            case .notAvailable: tracking = WF_VIO_TRACKING_NOT_AVAILABLE
            }
            var c = wf_vio_sample(t: s.t, east_m: s.east, north_m: s.north, yaw_rad: s.yawRad,
                                  tracking: Int32(tracking.rawValue))
            try check(wf_localizer_predict(raw, &c))
        }

        func noteVIOReset() throws {
            try check(wf_localizer_note_vio_reset(raw))
        }

        func updateSigns(_ sightings: [SignSighting], kindIds: [String: Int32], unsearchedKindIds: [Int32],
                         t: Double) throws {
            // Kinds the map does not have get id -1, which the core ignores.
            let obs = sightings.map {
                wf_sign_observation(kind: kindIds[$0.identityKey] ?? -1, range_m: $0.rangeMeters, bearing_rad: $0.bearingRad,
                                    score: $0.score, track_id: $0.track?.id ?? 0,
                                    track_range_m: $0.track?.earlierRangeMeters ?? .nan,
                                    track_bearing_rad: $0.track?.earlierBearingRad ?? .nan)
            }
            let status = obs.withUnsafeBufferPointer { o in
                unsearchedKindIds.withUnsafeBufferPointer { u in
                    wf_localizer_update_signs_searched(raw, o.baseAddress, o.count, t, u.baseAddress, u.count)
                }
            }
            try check(status)
        }

        func updateAltitude(_ meters: Double, t: Double) throws {
            try check(wf_localizer_update_altitude(raw, meters, t))
        }

        func updateCompass(headingInMapRad: Double, accuracyRad: Double, t: Double) throws {
            try check(wf_localizer_update_compass(raw, headingInMapRad, accuracyRad, t))
        }

        func setParameter(_ name: String, _ value: Double) throws {
            try check(name.withCString { wf_localizer_set_parameter(raw, $0, value) })
        }

        func parameter(_ name: String) throws -> Double {
            var v = 0.0
            try check(name.withCString { wf_localizer_get_parameter(raw, $0, &v) })
            return v
        }

        func estimate(floorIds: [String]) -> LocalizationEstimate {
            var e = wf_localizer_estimate()
            _ = wf_localizer_get_estimate(raw, &e)
            let floor = (e.floor_index >= 0 && Int(e.floor_index) < floorIds.count) ? floorIds[Int(e.floor_index)] : ""
            var estimate = LocalizationEstimate(
                t: e.t, positionInMap: Point2(x: e.x, y: e.y), floorId: floor, headingRad: e.heading_rad,
                covarianceXX: e.cov_xx, covarianceXY: e.cov_xy, covarianceYY: e.cov_yy,
                headingStdRad: e.heading_std_rad, confidence: e.confidence, isLocalized: e.localized != 0,
                hypothesisCount: Int(e.hypothesis_count), particleCount: Int(e.particle_count))
            estimate.hypotheses = hypotheses(floorIds: floorIds)
            estimate.unexplainedSightingNats = e.unexplained_sighting_nats
            estimate.sightingsUnexplained = e.sightings_unexplained != 0
            return estimate
        }

        private func hypotheses(floorIds: [String]) -> [PoseHypothesis] {
            var buffer = [wf_localizer_hypothesis](repeating: wf_localizer_hypothesis(), count: 16)
            var count = 0
            let status = buffer.withUnsafeMutableBufferPointer {
                wf_localizer_get_hypotheses(raw, $0.baseAddress, $0.count, &count)
            }
            guard status == WF_LOC_OK.rawValue else { return [] }
            return buffer.prefix(count).compactMap { h in
                guard h.floor_index >= 0, Int(h.floor_index) < floorIds.count else { return nil }
                return PoseHypothesis(weight: h.weight, floorId: floorIds[Int(h.floor_index)],
                                      positionInMap: Point2(x: h.x, y: h.y), headingRad: h.heading_rad,
                                      positionStdMeters: h.position_std_m, evidenceNats: h.evidence_nats,
                                      headingStdRad: h.heading_std_rad)
            }
        }

        func floorSymmetries(floorIndex: Int) -> [FloorSymmetry] {
            var buffer = [wf_localizer_floor_symmetry](repeating: wf_localizer_floor_symmetry(), count: 3)
            var count = 0
            let status = buffer.withUnsafeMutableBufferPointer {
                wf_localizer_get_floor_symmetries(raw, Int32(floorIndex), $0.baseAddress, $0.count, &count)
            }
            guard status == WF_LOC_OK.rawValue else { return [] }
            return buffer.prefix(count).map {
                FloorSymmetry(angleRad: $0.angle_rad, center: Point2(x: $0.center_x_m, y: $0.center_y_m),
                              matchedFraction: $0.matched_fraction)
            }
        }

        func particles(maxCount: Int, floorIds: [String]) -> [ParticleSample] {
            guard maxCount > 0 else { return [] }
            var buffer = [wf_localizer_particle](repeating: wf_localizer_particle(), count: maxCount)
            var count = 0
            let status = buffer.withUnsafeMutableBufferPointer {
                wf_localizer_get_particles(raw, $0.baseAddress, $0.count, &count)
            }
            guard status == WF_LOC_OK.rawValue else { return [] }
            return buffer.prefix(count).map { p in
                let f = Int(p.floor_index)
                return ParticleSample(position: Point2(x: Double(p.x), y: Double(p.y)), headingRad: Double(p.heading_rad),
                                      floorId: f >= 0 && f < floorIds.count ? floorIds[f] : "",
                                      weight: Double(p.weight), scale: Double(p.scale))
            }
        }
    }

    static func error(_ status: Int32, message: String) -> LocalizerError {
        let text = message.isEmpty ? String(cString: wf_localizer_status_string(status)) : message
        switch status {
        case WF_LOC_ERR_INVALID_ARGUMENT.rawValue: return .invalidArgument(text)
        case WF_LOC_ERR_OUT_OF_MEMORY.rawValue: return .outOfMemory(text)
        case WF_LOC_ERR_VERSION.rawValue: return .unsupportedVersion(text)
        case WF_LOC_ERR_INVALID_MAP.rawValue: return .invalidMap(text)
        case WF_LOC_ERR_NO_WALKABLE_SPACE.rawValue: return .noWalkableSpace(text)
        case WF_LOC_ERR_NOT_INITIALIZED.rawValue: return .notInitialized(text)
        case WF_LOC_ERR_NON_FINITE_INPUT.rawValue: return .nonFiniteInput(text)
        default: return .internalFailure(text)
        }
    }

    static func cDefaults() -> wf_localizer_options {
        var o = wf_localizer_options()
        _ = wf_localizer_options_init(&o, UInt32(WF_LOCALIZER_OPTIONS_VERSION))
        return o
    }

    static func defaultOptions() -> LocalizerOptions {
        let o = cDefaults()
        return LocalizerOptions(
            particleCount: Int(o.particle_count), minParticles: Int(o.min_particles), maxParticles: Int(o.max_particles),
            horizontalFieldOfViewRad: o.horizontal_fov_rad, maxSignRangeMeters: o.max_sign_range_m,
            negativeInformation: o.negative_information != 0, recovery: o.recovery != 0,
            adaptiveParticleCount: o.adaptive_particle_count != 0, rangeSigmaBaseMeters: o.range_sigma_base_m,
            rangeSigmaPerMeter: o.range_sigma_per_meter, bearingSigmaRad: o.bearing_sigma_rad,
            clutterProbability: o.clutter_probability, wallClearanceMeters: o.wall_clearance_m,
            gridCellMeters: o.grid_cell_m, maxViewAngleFromNormalRad: o.max_view_angle_from_normal_rad,
            startPointDoubtShare: o.start_point_doubt_share)
    }

    static func cOptions(_ s: LocalizerOptions) throws -> wf_localizer_options {
        func int32(_ v: Int, _ name: String) throws -> Int32 {
            guard let r = Int32(exactly: v) else { throw LocalizerError.invalidArgument("option \(name) = \(v) is out of range") }
            return r
        }
        var o = cDefaults()
        o.particle_count = try int32(s.particleCount, "particleCount")
        o.min_particles = try int32(s.minParticles, "minParticles")
        o.max_particles = try int32(s.maxParticles, "maxParticles")
        o.horizontal_fov_rad = s.horizontalFieldOfViewRad
        o.max_sign_range_m = s.maxSignRangeMeters
        o.negative_information = s.negativeInformation ? 1 : 0
        o.recovery = s.recovery ? 1 : 0
        o.adaptive_particle_count = s.adaptiveParticleCount ? 1 : 0
        o.range_sigma_base_m = s.rangeSigmaBaseMeters
        o.range_sigma_per_meter = s.rangeSigmaPerMeter
        o.bearing_sigma_rad = s.bearingSigmaRad
        o.clutter_probability = s.clutterProbability
        o.wall_clearance_m = s.wallClearanceMeters
        o.grid_cell_m = s.gridCellMeters
        o.max_view_angle_from_normal_rad = s.maxViewAngleFromNormalRad
        o.start_point_doubt_share = s.startPointDoubtShare
        return o
    }

    /// Flattens the building into the C map (copied by the core) and creates the handle.
    static func create(building: Building, kindIds: [String: Int32], options: LocalizerOptions,
                       seed: UInt64) throws -> Handle {
        var opts = try cOptions(options)
        let floors = building.floors
        let catalogue = building.signCatalogue
        // Per-floor flat arrays, kept alive until wf_localizer_create returns (it copies them).
        var walls: [[Float]] = []
        var signs: [[wf_localizer_sign]] = []
        var links: [[Float]] = []
        var seeds: [[Float]] = []
        for f in floors {
            walls.append(f.walls.flatMap { [Float($0.from.x), Float($0.from.y), Float($0.to.x), Float($0.to.y)] })
            signs.append(f.signs.map { sign in
                // The kind's own recognition limits (0 = the options').
                let spec = catalogue.spec(kind: sign.kind)
                return wf_localizer_sign(kind: kindIds[sign.identityKey] ?? 0, x: Float(sign.position.x), y: Float(sign.position.y),
                                         facing_x: Float(sign.facing.x), facing_y: Float(sign.facing.y),
                                         double_sided: sign.doubleSided ? 1 : 0,
                                         max_range_m: Float(spec?.maxRangeMeters ?? 0),
                                         max_view_angle_rad: Float((spec?.maxViewAngleDeg ?? 0) * .pi / 180))
            })
            let nodes = building.graph.nodes.filter { $0.floorId == f.id }
            seeds.append(nodes.flatMap { [Float($0.position.x), Float($0.position.y)] })
            links.append(nodes.filter { $0.kind == .verticalLink }.flatMap { [Float($0.position.x), Float($0.position.y)] })
        }
        let wallPtrs = walls.map(copyToHeap)
        let signPtrs = signs.map(copyToHeap)
        let linkPtrs = links.map(copyToHeap)
        let seedPtrs = seeds.map(copyToHeap)
        defer {
            (wallPtrs + linkPtrs + seedPtrs).forEach { $0?.deallocate() }
            signPtrs.forEach { $0?.deallocate() }
        }
        var cFloors: [wf_localizer_floor] = []
        for i in floors.indices {
            cFloors.append(wf_localizer_floor(
                elevation_m: floors[i].elevationMeters,
                walls: UnsafePointer(wallPtrs[i]), wall_count: walls[i].count / 4,
                signs: UnsafePointer(signPtrs[i]), sign_count: signs[i].count,
                link_points: UnsafePointer(linkPtrs[i]), link_point_count: links[i].count / 2,
                seed_points: UnsafePointer(seedPtrs[i]), seed_point_count: seeds[i].count / 2))
        }
        var out: OpaquePointer?
        let status = cFloors.withUnsafeBufferPointer { fb -> Int32 in
            var map = wf_localizer_map(version: UInt32(WF_LOCALIZER_MAP_VERSION), floors: fb.baseAddress,
                                       floor_count: fb.count, kind_count: Int32(kindIds.count))
            return wf_localizer_create(&out, &map, &opts, seed)
        }
        guard status == WF_LOC_OK.rawValue, let raw = out else {
            // The core's own reason (kept per thread, read with a NULL handle), never just the status's name.
            var reason = String(cString: wf_localizer_last_error(nil))
            if reason.isEmpty { reason = String(cString: wf_localizer_status_string(status)) }
            throw error(status, message: "building '\(building.id)': " + namingFloors(reason, floorIds: floors.map(\.id)))
        }
        return Handle(raw: raw)
    }

    /// The core names floors by index ("floor 1: ..."); adds the map's floor id: "floor 1 (id \"2\"): ...".
    static func namingFloors(_ message: String, floorIds: [String]) -> String {
        guard message.hasPrefix("floor "), let colon = message.firstIndex(of: ":") else { return message }
        let digits = message[message.index(message.startIndex, offsetBy: 6)..<colon]
        guard let i = Int(digits), floorIds.indices.contains(i) else { return message }
        return "floor \(i) (id \"\(floorIds[i])\")" + message[colon...]
    }

    /// A heap copy of `values` (nil when empty), to be deallocated by the caller.
    private static func copyToHeap<T>(_ values: [T]) -> UnsafeMutablePointer<T>? {
        guard !values.isEmpty else { return nil }
        let p = UnsafeMutablePointer<T>.allocate(capacity: values.count)
        p.initialize(from: values, count: values.count)
        return p
    }
}
