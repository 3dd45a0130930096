import Foundation
import SessionFormat
import SignDetection

/// One camera frame as the shared pipeline sees it, on the phone (built from an `ARFrame` by the thin
/// adapter in App/iOS) and on the command line (built from a recorded `FrameRecord`). Domain types only:
/// no ARKit or CoreVideo type crosses into the pipeline.
public struct PipelineFrame: Sendable {
    /// Timestamp, seconds.
    public var t: Double
    /// ARKit camera-to-world transform; nil when the pose was not finite (the frame is then skipped by
    /// the motion update and counted as lost tracking).
    public var cameraPose: CameraPose?
    /// ARKit tracking state.
    public var tracking: TrackingState
    /// Reason for limited tracking.
    public var trackingReason: TrackingReason?
    /// Intrinsics of the image, pixels.
    public var intrinsics: CameraIntrinsics
    /// Barometric altitude relative to the session start, meters.
    public var relativeAltitudeMeters: Double?
    /// Compass heading, degrees clockwise from north.
    public var compassHeadingDeg: Double?
    /// Core Location's accuracy of that heading, degrees (nil = unknown).
    public var compassAccuracyDeg: Double?
    /// The frame's pixels, when the detector should run on them (the phone: ARKit's captured image, luma
    /// plane or NV12). Takes precedence over `imagePath`.
    public var image: ImageBuffer?
    /// Path of the frame's image file, when the detector should run on it (replay of bundles with images).
    public var imagePath: String?
    /// Sign sightings already measured for this frame (recorded `observations.jsonl`, or simulation).
    public var measuredObservations: [ObservationRecord]
    /// Sign kinds the detector that measured `measuredObservations` did not look for on this frame
    /// (`FrameRecord.unsearchedSignKinds`); empty = every kind searched. Not used when the detector runs here.
    public var unsearchedSignKinds: Set<String> = []

    /// Creates a frame.
    public init(t: Double, cameraPose: CameraPose?, tracking: TrackingState, trackingReason: TrackingReason? = nil,
                intrinsics: CameraIntrinsics, relativeAltitudeMeters: Double? = nil, compassHeadingDeg: Double? = nil,
                image: ImageBuffer? = nil, imagePath: String? = nil, measuredObservations: [ObservationRecord] = []) {
        self.t = t; self.cameraPose = cameraPose; self.tracking = tracking; self.trackingReason = trackingReason
        self.intrinsics = intrinsics; self.relativeAltitudeMeters = relativeAltitudeMeters
        self.compassHeadingDeg = compassHeadingDeg; self.image = image; self.imagePath = imagePath
        self.measuredObservations = measuredObservations
    }

    /// Builds the pipeline frame of a recorded frame. `imagesDirectory` is the bundle's images/ folder.
    public init(record: FrameRecord, imagesDirectory: URL?, observations: [ObservationRecord] = []) {
        self.init(t: record.t, cameraPose: CameraPose(columnMajor: record.cameraToWorld), tracking: record.tracking,
                  trackingReason: record.trackingReason, intrinsics: record.intrinsics,
                  relativeAltitudeMeters: record.relativeAltitudeMeters, compassHeadingDeg: record.compassHeadingDeg,
                  imagePath: record.image.flatMap { name in imagesDirectory?.appendingPathComponent(name).path },
                  measuredObservations: observations)
        compassAccuracyDeg = record.compassAccuracyDeg
        unsearchedSignKinds = Set(record.unsearchedSignKinds ?? [])
    }
}
