import Foundation
import SessionFormat

/// What to do with one ARKit frame. Every frame is processed (motion update, compass, altitude, planes);
/// only the image and the JPEG are optional.
public struct FrameDecision: Sendable, Equatable {
    /// Convert the captured image for the detector and attach it to the pipeline frame.
    public var attachImage: Bool
    /// Encode a JPEG of the frame for the recording (recording with images on, every n-th frame).
    public var recordJPEG: Bool
}

/// Counters of the phone pipeline since `start`, for the device checklist (docs/ios.md) and logs.
public struct FrameStatistics: Sendable, Equatable {
    /// Frames that arrived from ARKit.
    public var arrived = 0
    /// Frames the pipeline finished (each one a motion update).
    public var processed = 0
    /// Frames that carried an image to the detector.
    public var detected = 0
    /// Largest number of frames waiting for the pipeline at once.
    public var maxBacklog = 0
    /// Total pipeline time, seconds (detection included).
    public var processingSeconds = 0.0
    /// Total detection time, seconds.
    public var detectionSeconds = 0.0
    /// First and last frame times, seconds.
    public var firstT: Double?
    /// Last frame time, seconds.
    public var lastT: Double?

    /// Frames processed per second of walk.
    public var processedHz: Double {
        guard let a = firstT, let b = lastT, b > a else { return 0 }
        return Double(processed) / (b - a)
    }
    /// Detections per second of walk.
    public var detectedHz: Double {
        guard let a = firstT, let b = lastT, b > a else { return 0 }
        return Double(detected) / (b - a)
    }
    /// Share of one core the pipeline used (processing time / walk time).
    public var coreShare: Double {
        guard let a = firstT, let b = lastT, b > a else { return 0 }
        return processingSeconds / (b - a)
    }
}

/// The phone's frame scheduling, shared logic the SensorHub adapter runs per ARKit frame: ARKit delivers
/// frames on the session's delegate queue; each one is decided here, converted, and handed to the
/// pipeline's own serial queue (never the main queue). Every frame reaches the motion update; the detector
/// gets an image only when `DetectorScheduler` says so (its rate, time budget, thermal state and the
/// pipeline backlog). Not thread-safe: call from the delegate queue, and report `frameProcessed` back on it.
public struct FrameScheduler: Sendable {
    /// The detector throttle.
    public var detector = DetectorScheduler()
    /// Recording with images: JPEG every `recordImageEveryNthFrame` frames (nil = no images recorded).
    public var recordImageEveryNthFrame: Int?
    /// Counters.
    public private(set) var statistics = FrameStatistics()
    private var frameIndex = 0

    /// Frames handed to the pipeline and not yet finished.
    public var backlogFrames: Int { statistics.arrived - statistics.processed }

    /// Creates a scheduler.
    public init(detector: DetectorScheduler = DetectorScheduler(), recordImageEveryNthFrame: Int? = nil) {
        self.detector = detector
        self.recordImageEveryNthFrame = recordImageEveryNthFrame
    }

    /// A frame at `t` (seconds) arrived; it goes to the pipeline in any case.
    public mutating func frameArrived(t: Double) -> FrameDecision {
        let backlog = backlogFrames
        statistics.arrived += 1
        statistics.maxBacklog = max(statistics.maxBacklog, backlog + 1)
        if statistics.firstT == nil { statistics.firstT = t }
        statistics.lastT = t
        frameIndex += 1
        let attach = detector.shouldDetect(t: t, backlogFrames: backlog)
        let jpeg = recordImageEveryNthFrame.map { frameIndex % max(1, $0) == 0 } ?? false
        return FrameDecision(attachImage: attach, recordJPEG: jpeg)
    }

    /// The pipeline finished a frame: `processingSeconds` in all, `detectionSeconds` when it carried an image
    /// (nil otherwise). Frees the detector for the next image.
    public mutating func frameProcessed(processingSeconds: Double, detectionSeconds: Double?) {
        statistics.processed += 1
        if processingSeconds.isFinite, processingSeconds >= 0 { statistics.processingSeconds += processingSeconds }
        if let d = detectionSeconds {
            statistics.detected += 1
            if d.isFinite, d >= 0 { statistics.detectionSeconds += d }
            detector.detectionFinished(durationSeconds: d)
        }
    }

    /// The frame could not be converted (non-finite intrinsics...): it never reached the pipeline.
    public mutating func frameDiscarded(hadImage: Bool) {
        statistics.arrived -= 1
        if hadImage { detector.detectionFinished() }
    }
}
