#if canImport(ARKit) && canImport(CoreMotion) && canImport(CoreLocation) && os(iOS)
import ARKit
import CoreLocation
import CoreMotion
import SessionFormat
import WayfinderCore

/// Thin ARKit / Core Motion / Core Location adapter: reads each `ARFrame`'s fields and hands plain numbers
/// to `FrameConversion` (logic tested on Linux). Frames are dropped, not queued, while the pipeline is busy
/// (`DetectorScheduler`); the captured pixel buffer is not copied unless a recording needs a JPEG.
final class SensorHub: NSObject, ARSessionDelegate, CLLocationManagerDelegate {
    /// Called on the main queue with each accepted frame, its mean luma (covered-camera check) and, while
    /// recording, a subsampled JPEG.
    var onFrame: ((PipelineFrame, Double?, Data?) -> Void)?
    var recordImages = false
    /// Called on the main queue with vertical plane-anchor events (PlaneAnchorForwarding.swift).
    var onPlanes: (([PlaneRecord]) -> Void)?

    private let session = ARSession()
    private let altimeter = CMAltimeter()
    private let location = CLLocationManager()
    private var relativeAltitudeMeters: Double?
    private var headingDeg: Double?
    private var headingAccuracyDeg: Double?
    private var scheduler = DetectorScheduler()
    private let thermal = ThermalMonitor()
    private var frameCount = 0

    func start() {
        let configuration = ARWorldTrackingConfiguration()
        configuration.worldAlignment = .gravity
        configuration.planeDetection = [.vertical]   // walls, scored against the map (PlaneAnchorForwarding)
        session.delegate = self
        session.run(configuration, options: [.resetTracking, .removeExistingAnchors])
        if CMAltimeter.isRelativeAltitudeAvailable() {
            altimeter.startRelativeAltitudeUpdates(to: .main) { [weak self] data, _ in
                self?.relativeAltitudeMeters = data?.relativeAltitude.doubleValue
            }
        }
        location.delegate = self
        location.requestWhenInUseAuthorization()
        if CLLocationManager.headingAvailable() { location.startUpdatingHeading() }
        thermal.onChange = { [weak self] level, lowPower in
            self?.scheduler.thermal = level
            self?.scheduler.lowPower = lowPower
        }
        thermal.start()
    }

    func stop() {
        session.pause()
        altimeter.stopRelativeAltitudeUpdates()
        location.stopUpdatingHeading()
        thermal.stop()
    }

    func locationManager(_ manager: CLLocationManager, didUpdateHeading newHeading: CLHeading) {
        // Magnetic, not true, heading: the map's compassHeadingOfMapNorthDeg is what a compass reads.
        headingDeg = FrameConversion.compassHeadingDeg(newHeading.magneticHeading,
                                                       accuracyDeg: newHeading.headingAccuracy)
        headingAccuracyDeg = newHeading.headingAccuracy
    }

    func session(_ session: ARSession, didUpdate frame: ARFrame) {
        guard scheduler.shouldDetect(t: frame.timestamp) else { return }
        let camera = frame.camera
        let t = camera.transform
        let k = camera.intrinsics
        let (state, reason) = Self.describe(camera.trackingState)
        let pixelBuffer = frame.capturedImage
        guard let pipelineFrame = FrameConversion.pipelineFrame(
            t: frame.timestamp,
            transformColumns: [[t.columns.0.x, t.columns.0.y, t.columns.0.z, t.columns.0.w],
                               [t.columns.1.x, t.columns.1.y, t.columns.1.z, t.columns.1.w],
                               [t.columns.2.x, t.columns.2.y, t.columns.2.z, t.columns.2.w],
                               [t.columns.3.x, t.columns.3.y, t.columns.3.z, t.columns.3.w]],
            intrinsicsColumns: [[k.columns.0.x, k.columns.0.y, k.columns.0.z],
                                [k.columns.1.x, k.columns.1.y, k.columns.1.z],
                                [k.columns.2.x, k.columns.2.y, k.columns.2.z]],
            imageWidth: CVPixelBufferGetWidth(pixelBuffer), imageHeight: CVPixelBufferGetHeight(pixelBuffer),
            trackingState: state, trackingReason: reason,
            relativeAltitudeMeters: relativeAltitudeMeters, compassHeadingDeg: headingDeg,
            compassAccuracyDeg: headingAccuracyDeg,
            image: PixelBufferTools.lumaImage(pixelBuffer)) else {
            scheduler.detectionFinished()
            return
        }
        frameCount += 1
        let luma = PixelBufferTools.meanLuma(pixelBuffer)
        let jpeg = recordImages && frameCount % 10 == 0 ? PixelBufferTools.jpeg(pixelBuffer) : nil
        DispatchQueue.main.async { [weak self] in
            self?.onFrame?(pipelineFrame, luma, jpeg)
            self?.scheduler.detectionFinished()
        }
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
