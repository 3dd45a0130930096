import Maps

/// Particle-filter localizer over one building: fuses ARKit VIO with sign sightings, walls and barometric
/// altitude (Fusco & Coughlan 2020; algorithm in docs/localizer.md). Owns a handle of the C++ core and frees
/// it when deallocated. Not thread-safe: use one instance from one thread (or actor) at a time.
public final class ParticleLocalizer {
    private let handle: LocalizerBridge.Handle
    private let floorIds: [String]
    private let floorIndexById: [String: Int32]
    private let kindIds: [String: Int32]
    /// The core's kind ids of each sign kind: one per identity (`kind` alone, or `kind#legend`).
    private let kindIdsByKind: [String: [Int32]]

    /// The last input (predict / update / compass) that was rejected, e.g. NaN; nil after a good one.
    public private(set) var lastInputError: LocalizerError?

    /// Builds the filter's map from `building` (walls, signs, vertical-link nodes, graph nodes as flood-fill
    /// seeds per floor) and precomputes its grids. Throws `LocalizerError.invalidMap` / `.invalidArgument`.
    ///
    /// `parameters` sets internal model parameters by name (`setParameter`), e.g. `["compass.enabled": 0]`.
    public init(building: Building, options: LocalizerOptions = LocalizerOptions(), parameters: [String: Double] = [:],
                seed: UInt64 = 1) throws {
        floorIds = building.floors.map(\.id)
        var byId: [String: Int32] = [:]
        for (i, f) in building.floors.enumerated() { byId[f.id] = Int32(i) }
        floorIndexById = byId
        let kinds = Set(building.floors.flatMap { $0.signs.map(\.identityKey) }).sorted()
        var kindIds: [String: Int32] = [:]
        for (i, k) in kinds.enumerated() { kindIds[k] = Int32(i) }
        self.kindIds = kindIds
        var byKind: [String: Set<Int32>] = [:]
        for sign in building.floors.flatMap(\.signs) { byKind[sign.kind, default: []].insert(kindIds[sign.identityKey]!) }
        kindIdsByKind = byKind.mapValues { $0.sorted() }
        handle = try LocalizerBridge.create(building: building, kindIds: kindIds, options: options, seed: seed)
        for (name, value) in parameters.sorted(by: { $0.key < $1.key }) { try handle.setParameter(name, value) }
    }

    /// Sets an internal model parameter by name ("compass.enabled", "compass.kappa", "compass.outlier_share",
    /// "compass.min_distance_m", "compass.max_nats", "compass.max_total_nats", "lock.rival_weight", "lock.rival_margin_nats",
    /// "lock.jump_m", "sign.negative_info_min_range_m"; docs/localizer.md). Throws `.invalidArgument` naming the known names or the range.
    public func setParameter(_ name: String, _ value: Double) throws { try handle.setParameter(name, value) }

    /// Reads an internal model parameter by name. Throws `.invalidArgument` for an unknown name.
    public func parameter(_ name: String) throws -> Double { try handle.parameter(name) }

    /// Restarts the filter from `prior`. Throws `.unknownFloor`, `.noWalkableSpace`, `.invalidArgument`.
    public func reset(prior: LocalizerPrior) throws {
        switch prior {
        case .floorOnly(let floorId):
            guard let f = floorIndexById[floorId] else { throw LocalizerError.unknownFloor(floorId) }
            try handle.initFloorOnly(floor: f)
        case .startPoint(let floorId, let position, let radiusMeters):
            guard let f = floorIndexById[floorId] else { throw LocalizerError.unknownFloor(floorId) }
            try handle.initStartPoint(floor: f, x: position.x, y: position.y, radiusMeters: radiusMeters)
        }
        lastInputError = nil
    }

    /// Compass prior: camera heading in the map `headingInMapRad` +- `sigmaRad`. Applied at the next reset
    /// (or, when no VIO yaw is known yet or the filter runs already, as a reweighting at the next predict).
    /// Invalid values are ignored and reported in `lastInputError`.
    public func setCompassPrior(headingInMapRad: Double, sigmaRad: Double) {
        record { try handle.setCompassPrior(headingInMapRad: headingInMapRad, sigmaRad: sigmaRad) }
    }

    /// Motion update from one VIO sample. Non-finite samples are ignored (`lastInputError`).
    public func predict(_ sample: VIOSample) {
        record { try handle.predict(sample) }
    }

    /// The VIO origin was reset (world tracking restarted): the next sample starts a new VIO frame, whose delta
    /// is skipped with the traveler's map heading kept (`wf_localizer_note_vio_reset`).
    public func noteVIOReset() {
        record { try handle.noteVIOReset() }
    }

    /// Measurement update with the sightings of one frame at time `t` (seconds). An empty array is a frame
    /// without detections (negative information). Before a reset this does nothing (`lastInputError`).
    public func update(sightings: [SignSighting], t: Double) {
        update(sightings: sightings, unsearchedKinds: [], t: t)
    }

    /// The same for a frame on which the detector did not look for the kinds `unsearchedKinds` (kind names, e.g.
    /// `SensedFrame.unsearchedKinds`): the signs of those kinds, legends included, take no negative information on
    /// this frame (their absence says nothing). Names the map does not have are left out.
    public func update(sightings: [SignSighting], unsearchedKinds: Set<String>, t: Double) {
        let ids = unsearchedKinds.sorted().flatMap { kindIdsByKind[$0] ?? [] }
        record { try handle.updateSigns(sightings, kindIds: kindIds, unsearchedKindIds: ids, t: t) }
    }

    /// Compass evidence: the camera heading in the map `headingInMapRad` (radians CCW from map +x) with Core
    /// Location's accuracy `accuracyRad` (nil = unknown) at `t`. Give every reading: the filter applies one at
    /// most once per few meters walked (spatially correlated indoor disturbance, docs/compass.md). Invalid
    /// readings are ignored and reported in `lastInputError`.
    public func updateCompass(headingInMapRad: Double, accuracyRad: Double?, t: Double) {
        record { try handle.updateCompass(headingInMapRad: headingInMapRad, accuracyRad: accuracyRad ?? 0, t: t) }
    }

    /// Measurement update with the vertical planes ARKit currently reports (valid in the current VIO session)
    /// at time `t` (seconds): a likelihood field against the map's walls (docs/localizer.md). Non-finite planes
    /// are skipped and reported in `lastInputError`; zero-width ones are ignored.
    public func updatePlanes(_ planes: [PlaneObservation], t: Double) {
        record { try handle.updatePlanes(planes, t: t) }
    }

    /// Barometric relative altitude (meters, any origin) at time `t`: a settled change of about a storey
    /// near an elevator or stairs moves the hypotheses to the floor of matching elevation.
    public func updateAltitude(relativeAltitudeMeters: Double, t: Double) {
        record { try handle.updateAltitude(relativeAltitudeMeters, t: t) }
    }

    /// The rotations that map the walls of floor `floorId` onto themselves (docs/localizer.md "Symmetric twins"):
    /// on such a floor the localizer does not settle until the evidence refutes each hypothesis's turned twin.
    /// Empty for an asymmetric or unknown floor.
    public func floorSymmetries(floorId: String) -> [FloorSymmetry] {
        guard let index = floorIds.firstIndex(of: floorId) else { return [] }
        return handle.floorSymmetries(floorIndex: index)
    }

    /// The current estimate (dominant hypothesis, confidence, localized flag).
    public var estimate: LocalizationEstimate {
        handle.estimate(floorIds: floorIds)
    }

    /// Up to `maxCount` particles (an even subsample when there are more), for drawing.
    public func particleSnapshot(maxCount: Int) -> [ParticleSample] {
        handle.particles(maxCount: max(0, maxCount), floorIds: floorIds)
    }

    private func record(_ body: () throws -> Void) {
        do {
            try body()
            lastInputError = nil
        } catch let e as LocalizerError {
            lastInputError = e
        } catch {
            lastInputError = .internalFailure("\(error)")
        }
    }
}
