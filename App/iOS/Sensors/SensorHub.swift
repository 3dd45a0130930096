#if canImport(ARKit) && canImport(CoreMotion) && canImport(CoreLocation) && os(iOS)
import ARKit
import CoreLocation
import CoreMotion
import SessionFormat
import WayfinderCore

/// Thin ARKit / Core Motion / Core Location adapter. ARKit calls it on its own serial `queue` (never the
/// main queue); for every ARFrame it asks the shared `FrameScheduler` whether the frame carries an image
/// for the detector (rate, time budget, thermal state, backlog) and a JPEG for the recording, reads the
/// frame's fields into plain numbers for `FrameConversion`, and hands *every* frame to the
/// `PipelineWorker` (the motion update runs on all of them, the same `WayfinderPipeline` as replay). Health
/// events (failure, interruption, tracking) go to the main queue for `SessionHealth`.
/// `@unchecked Sendable`: mutable state is touched only on `queue`.
final class SensorHub: NSObject, ARSessionDelegate, CLLocationManagerDelegate, @unchecked Sendable {
    /// The pipeline every frame goes to.
    let worker: PipelineWorker
    /// Main queue: camera-session health events.
    var onHealth: (@MainActor @Sendable (HealthEvent) -> Void)?

    private let queue = DispatchQueue(label: "org.wayfinder.arframes", qos: .userInitiated)
    private let session = ARSession()
    private let altimeter = CMAltimeter()
    private let location = CLLocationManager()
    private let thermal = ThermalMonitor()
    // Touched only on `queue`:
    private var scheduler = FrameScheduler()
    private var detectorMaxLongSidePx: Int?
    private var relativeAltitudeMeters: Double?
    private var headingDeg: Double?
    private var headingAccuracyDeg: Double?
    private var lastHealthT = -Double.infinity
    private var lastHealthState: String?

    init(worker: PipelineWorker) {
        self.worker = worker
        super.init()
        session.delegate = self
        session.delegateQueue = queue
    }

    /// Applies the settings of the next walk: recorded images (`AppSettings.recordImages`, every n-th frame
    /// while recording) and the detector's input size.
    func configure(recording: Bool, settings: AppSettings, sightingSource: SightingSource) {
        let every = recording && settings.recordImages ? settings.recordImageEveryNthFrame : nil
        let maxSide = DetectorInputGeometry.maxLongSidePx(for: sightingSource)
        queue.async { [self] in
            scheduler = FrameScheduler(detector: scheduler.detector, recordImageEveryNthFrame: every)
            detectorMaxLongSidePx = maxSide
        }
    }

    /// Frame statistics of the walk so far (for the device checklist's log line).
    func statistics(_ reply: @escaping @Sendable (FrameStatistics) -> Void) { queue.async { [self] in reply(scheduler.statistics) } }

    func start() {
        let configuration = ARWorldTrackingConfiguration()
        configuration.worldAlignment = .gravity
        configuration.planeDetection = [.vertical]   // walls, scored against the map (PlaneAnchorForwarding)
        let formats = ARWorldTrackingConfiguration.supportedVideoFormats
        let options = formats.map { VideoFormatOption(width: Int($0.imageResolution.width), height: Int($0.imageResolution.height),
                                                      framesPerSecond: $0.framesPerSecond) }
        if let i = VideoFormatOption.preferredIndex(options) { configuration.videoFormat = formats[i] }
        session.run(configuration, options: [.resetTracking, .removeExistingAnchors])
        let now = CACurrentMediaTime()
        post(.sessionStarted(t: now))
        if CMAltimeter.isRelativeAltitudeAvailable() {
            let operations = OperationQueue()
            operations.underlyingQueue = queue
            altimeter.startRelativeAltitudeUpdates(to: operations) { [weak self] data, _ in
                self?.relativeAltitudeMeters = data?.relativeAltitude.doubleValue
            }
        }
        location.delegate = self
        location.requestWhenInUseAuthorization()
        if CLLocationManager.headingAvailable() { location.startUpdatingHeading() }
        thermal.onChange = { [weak self] level, lowPower in
            guard let self else { return }
            self.queue.async {
                self.scheduler.detector.thermal = level
                self.scheduler.detector.lowPower = lowPower
            }
            self.post(.thermal(level))
        }
        thermal.start()
    }

    /// Restarts world tracking from scratch with the running configuration (SessionHealth's
    /// `.restartTracking`: relocalization did not succeed in time). The frames then report notAvailable and
    /// initializing, which the pipeline takes as a VIO reset; the particle filter keeps its particles.
    func restartTracking() {
        guard let configuration = session.configuration else { return }
        session.run(configuration, options: [.resetTracking, .removeExistingAnchors])
    }

    func stop() {
        session.pause()
        altimeter.stopRelativeAltitudeUpdates()
        location.stopUpdatingHeading()
        thermal.stop()
    }

    func locationManager(_ manager: CLLocationManager, didUpdateHeading newHeading: CLHeading) {
        // Magnetic, not true, heading: the map's compassHeadingOfMapNorthDeg is what a compass reads.
        let heading = FrameConversion.compassHeadingDeg(newHeading.magneticHeading, accuracyDeg: newHeading.headingAccuracy)
        let accuracy = newHeading.headingAccuracy
        queue.async { [self] in
            headingDeg = heading
            headingAccuracyDeg = accuracy
        }
    }

    // MARK: ARSessionDelegate (on `queue`)

    func session(_ session: ARSession, didUpdate frame: ARFrame) {
        let decision = scheduler.frameArrived(t: frame.timestamp)
        let camera = frame.camera
        let t = camera.transform
        let k = camera.intrinsics
        let (state, reason) = Self.describe(camera.trackingState)
        let pixelBuffer = frame.capturedImage
        let width = CVPixelBufferGetWidth(pixelBuffer), height = CVPixelBufferGetHeight(pixelBuffer)
        guard let geometry = DetectorInputGeometry(captureWidth: width, captureHeight: height, maxLongSidePx: detectorMaxLongSidePx),
              var pipelineFrame = FrameConversion.pipelineFrame(
                t: frame.timestamp,
                transformColumns: [[t.columns.0.x, t.columns.0.y, t.columns.0.z, t.columns.0.w],
                                   [t.columns.1.x, t.columns.1.y, t.columns.1.z, t.columns.1.w],
                                   [t.columns.2.x, t.columns.2.y, t.columns.2.z, t.columns.2.w],
                                   [t.columns.3.x, t.columns.3.y, t.columns.3.z, t.columns.3.w]],
                intrinsicsColumns: [[k.columns.0.x, k.columns.0.y, k.columns.0.z],
                                    [k.columns.1.x, k.columns.1.y, k.columns.1.z],
                                    [k.columns.2.x, k.columns.2.y, k.columns.2.z]],
                imageWidth: width, imageHeight: height, trackingState: state, trackingReason: reason,
                relativeAltitudeMeters: relativeAltitudeMeters, compassHeadingDeg: headingDeg,
                compassAccuracyDeg: headingAccuracyDeg) else {
            scheduler.frameDiscarded(hadImage: decision.attachImage)
            return
        }
        // Intrinsics of the image the detector (and the recording) sees.
        pipelineFrame.intrinsics = geometry.scaled(pipelineFrame.intrinsics)
        var hadImage = false
        if decision.attachImage, pipelineFrame.cameraPose != nil, let image = PixelBufferTools.bgraImage(pixelBuffer, geometry: geometry) {
            pipelineFrame.image = image
            hadImage = true
        } else if decision.attachImage {
            scheduler.detector.detectionFinished()
        }
        let luma = PixelBufferTools.meanLuma(pixelBuffer)
        let jpeg = decision.recordJPEG ? PixelBufferTools.jpeg(pixelBuffer, geometry: geometry) : nil
        let detected = hadImage
        worker.process(pipelineFrame, meanLuma: luma, jpeg: jpeg) { [weak self] seconds in
            guard let self else { return }
            // A detected frame's time is its detection time (the motion update's ~1 ms included).
            self.queue.async { self.scheduler.frameProcessed(processingSeconds: seconds, detectionSeconds: detected ? seconds : nil) }
        }
        // Health: on a change of tracking state, else twice a second (the watchdog needs freshness only).
        let described = state + (reason ?? "")
        if described != lastHealthState || frame.timestamp - lastHealthT >= 0.5 {
            lastHealthState = described
            lastHealthT = frame.timestamp
            let (ts, tr) = FrameConversion.tracking(state: state, reason: reason)
            post(.frame(t: frame.timestamp, tracking: pipelineFrame.cameraPose == nil ? .notAvailable : ts, reason: tr))
        }
    }

    func session(_ session: ARSession, didFailWithError error: Error) {
        let failure: SessionFailure
        switch (error as? ARError)?.code {
        case .cameraUnauthorized?: failure = .cameraUnauthorized
        case .unsupportedConfiguration?: failure = .unsupportedConfiguration
        default: failure = .sensorFailed
        }
        post(.sessionFailed(failure))
    }

    func sessionWasInterrupted(_ session: ARSession) { post(.interrupted(t: CACurrentMediaTime())) }

    func sessionInterruptionEnded(_ session: ARSession) { post(.interruptionEnded(t: CACurrentMediaTime())) }

    /// Relocalize after an interruption rather than reset: the world origin (and so the particle filter's
    /// VIO frame) is kept when ARKit recognises the place.
    func sessionShouldAttemptRelocalization(_ session: ARSession) -> Bool { true }

    private func post(_ event: HealthEvent) {
        DispatchQueue.main.async { [onHealth] in MainActor.assumeIsolated { onHealth?(event) } }
    }

    static func describe(_ state: ARCamera.TrackingState) -> (String, String?) {
        switch state {
        case .normal: return ("normal", nil)
        case .notAvailable: return ("notAvailable", nil)
        case .limited(let reason):
            switch reason {
            case .initializing: return ("limited", "initializing")
            case .excessiveMotion: return ("limited", "excessiveMotion")
            case .insufficientFeatures: return ("limited", "insufficientFeatures")
            case .relocalizing: return ("limited", "relocalizing")
            @unknown default: return ("limited", nil)
            }
        }
    }
}
#endif
