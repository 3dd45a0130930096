import Foundation

/// One frame's ranged signs (`SignDetector.senseFrame`) and the kinds the frame did not look for.
public struct SensedFrame: Sendable {
    /// Ranged signs, highest score first.
    public var signs: [SensedSign]
    /// Kinds of `SignDetector.kinds` this frame did not look for: all of them for a skipped (dark) frame, and the
    /// wall kinds whose turn had not come (the detector searches them in turn: docs/sign-detection.md "More sign
    /// kinds"). A localizer must not count their absence as a miss.
    public var unsearchedKinds: Set<String>
    /// Why the frame was skipped or truncated (a warning, not an error), or nil.
    public var warning: String?
}

/// The result of one frame: detections, or the reason the frame was skipped (dark frame).
public struct DetectionOutcome: Sendable {
    /// Detections, highest score first.
    public var detections: [SignDetection]
    /// Why the frame was skipped or truncated (a warning, not an error), or nil.
    public var warning: String?
}

/// The run-time sign perception (C++/OpenCV behind a C ABI): unrolls each frame by the camera roll, detects
/// signs with cascades or a U-Net, measures them by vertical slices and (`sense`) ranges them with the sizes of
/// the sign-kind catalogue (Fusco et al. 2020, section 3).
///
/// Owns its C handle (models loaded once) and frees it on deinit. Calls are serialised by an internal lock,
/// so one instance may be shared across tasks; for parallel throughput create one per task.
public final class SignDetector: @unchecked Sendable {
    /// The configuration the detector was created with.
    public let configuration: DetectorConfiguration
    /// Kind names it reports (cascade kinds, or U-Net classes without background).
    public let kinds: [String]

    private let handle: CDetector
    private let lock = NSLock()

    /// Loads the models. Throws `SignDetectorError.modelLoad` naming a missing or unreadable file, or
    /// `.invalidArgument` for an impossible configuration.
    public init(configuration: DetectorConfiguration) throws {
        self.configuration = configuration
        self.handle = try CDetector(configuration: configuration)
        self.kinds = handle.kinds
    }

    /// Detects signs in one frame.
    /// - Parameters:
    ///   - image: the raw camera image (sensor orientation, as captured).
    ///   - fx, fy, cx, cy: pinhole intrinsics of `image`, pixels (scale them with the image).
    ///   - pitchRad: elevation of the optical axis, radians, positive looking up.
    ///   - rollRad: ARKit Euler roll, radians (0 = landscape upright, -pi/2 = portrait).
    /// - Returns: detections, highest score first; [] for a skipped (dark) frame.
    /// - Throws: `SignDetectorError.badFrame` for an empty frame, intrinsics of another resolution,
    ///   non-finite values or pixel data shorter than described; `.internalFailure` for an OpenCV failure.
    public func detect(image: ImageBuffer, fx: Double, fy: Double, cx: Double, cy: Double,
                       pitchRad: Double, rollRad: Double) throws -> [SignDetection] {
        try detectFrame(image: image, fx: fx, fy: fy, cx: cx, cy: cy, pitchRad: pitchRad, rollRad: rollRad).detections
    }

    /// As `detect`, also returning the warning of a skipped frame.
    public func detectFrame(image: ImageBuffer, fx: Double, fy: Double, cx: Double, cy: Double,
                            pitchRad: Double, rollRad: Double) throws -> DetectionOutcome {
        try image.validate()
        lock.lock()
        defer { lock.unlock() }
        return try handle.detect(image: image, intrinsics: (fx, fy, cx, cy), pitchRad: pitchRad, rollRad: rollRad)
    }

    /// The whole perception of one frame in one C call (wf_detector_sense): detection, slice measurement and
    /// the apparent-height range of each sign with its kind's face height from `configuration.catalogue`.
    /// Parameters as `detect`; `pitchRad` and `rollRad` are the camera pose (from gravity) the range uses.
    /// - Returns: ranged signs, highest score first; [] for a skipped (dark) frame. Detections of kinds outside
    ///   the catalogue, and measurements without a finite positive range, are left out.
    /// - Throws: `SignDetectorError.invalidCatalogue` when the configuration has no catalogue, `.badFrame` for
    ///   a frame of the wrong size or stride or a non-finite pose, `.internalFailure` for an OpenCV failure.
    public func sense(image: ImageBuffer, fx: Double, fy: Double, cx: Double, cy: Double,
                      pitchRad: Double, rollRad: Double) throws -> [SensedSign] {
        try image.validate()
        lock.lock()
        defer { lock.unlock() }
        return try handle.sense(image: image, intrinsics: (fx, fy, cx, cy), pitchRad: pitchRad, rollRad: rollRad).signs
    }

    /// As `sense`, also returning the kinds this frame did not look for (`SensedFrame.unsearchedKinds`: a rejected
    /// frame's, or the wall kinds whose turn in the detector's schedule had not come), whose absence says nothing.
    public func senseFrame(image: ImageBuffer, fx: Double, fy: Double, cx: Double, cy: Double,
                           pitchRad: Double, rollRad: Double) throws -> SensedFrame {
        try image.validate()
        lock.lock()
        defer { lock.unlock() }
        let (signs, warning) = try handle.sense(image: image, intrinsics: (fx, fy, cx, cy), pitchRad: pitchRad,
                                               rollRad: rollRad)
        return SensedFrame(signs: signs, unsearchedKinds: handle.unsearchedKinds, warning: warning)
    }

    /// The kinds the detector searches in turn, a few per frame (the wall kinds: pictograms and placards, whose
    /// cascades run beside the U-Net), in its order; the others are searched on every frame.
    public var wallKinds: [String] { handle.wallKinds }

    /// The next `sense`/`senseFrame`/`detect` call looks for exactly these wall kinds (none for an empty set), instead
    /// of the ones the detector's own schedule would take; for that one frame (wf_detector_request_wall_kinds).
    /// - Throws: `SignDetectorError.invalidArgument` for a name that is not one of `wallKinds`.
    public func requestWallKinds(_ names: Set<String>) throws {
        lock.lock()
        defer { lock.unlock() }
        try handle.requestWallKinds(names)
    }

    /// Version of the linked C library.
    public static var libraryVersion: String { CDetector.libraryVersion }
}
