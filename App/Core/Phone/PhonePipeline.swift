import Foundation
import Maps
import SessionFormat

/// The phone's end of "the same pipeline as replay": owns the `GuidanceSession` (and through it the
/// `WayfinderPipeline`) on the pipeline's serial queue, and starts guidance the way `Replay.run` does: the
/// pipeline is built at the first frame with a pose, with `Replay.options`'s rules (the chosen floor,
/// start and destination; the localizer's field of view from that frame's intrinsics and roll), the
/// traveler's settings applied (`AppSettings.pipelineOptions`). Every frame goes to `process` (motion
/// update every frame, detection on frames that carry an image); plane events go to `ingest` as they come
/// and are scored at the next frame, as in replay. Not thread-safe: use from one queue.
public final class PhonePipeline {
    /// The app flow (pickers, guidance).
    public let session: GuidanceSession
    /// Settings used at the next start.
    public var settings: AppSettings
    /// Base pipeline options (detector, seed, particle count) before settings and the first frame.
    public var baseOptions: PipelineOptions
    /// True between `requestStart` and the first frame with a pose.
    public private(set) var startPending = false

    /// Wraps a session.
    public init(session: GuidanceSession = GuidanceSession(), settings: AppSettings = AppSettings(),
                baseOptions: PipelineOptions = PipelineOptions()) {
        self.session = session
        self.settings = settings
        self.baseOptions = baseOptions
    }

    /// The options for a walk whose first posed frame has `intrinsics` and camera roll `rollRad`: the same
    /// field-of-view rule as `Replay.options`, then the settings.
    public func options(firstIntrinsics intrinsics: CameraIntrinsics, rollRad: Double) -> PipelineOptions {
        var o = settings.pipelineOptions(base: baseOptions)
        o.localizer.horizontalFieldOfViewRad = Replay.horizontalFieldOfViewRad(intrinsics: intrinsics, rollRad: rollRad)
        return o
    }

    /// Guidance was asked for (permission fine, sensors starting): it starts at the next frame with a pose.
    /// Throws when the session is not ready (no building, start or destination chosen).
    public func requestStart() throws {
        guard session.state == .ready else {
            throw PipelineError.invalidConfiguration("choose a building, a start and a destination first")
        }
        startPending = true
    }

    /// Stops guidance (or a pending start).
    public func stop() -> [GuidanceCommand] {
        startPending = false
        return session.stop()
    }

    /// One frame: starts the pending walk on the first posed frame, then runs the pipeline. A failed
    /// start (unknown place, missing model) is thrown with its message; nothing else throws.
    public func process(_ frame: PipelineFrame, meanLuma: Double? = nil) throws -> [GuidanceCommand] {
        var out: [GuidanceCommand] = []
        if startPending, let pose = frame.cameraPose {
            startPending = false
            session.pipelineOptions = options(firstIntrinsics: frame.intrinsics, rollRad: pose.rollRad)
            // .startSensors is already done: the sensors deliver this frame.
            out += try session.start().filter { $0 != .startSensors }
        }
        out += session.process(frame, meanLuma: meanLuma)
        return out
    }

    /// ARKit plane events, scored at the next frame.
    public func ingest(planes: [PlaneRecord]) { session.ingest(planes: planes) }
}
