#if canImport(UIKit) && os(iOS)
import Foundation
import Maps
import SessionFormat
import UIKit
import WayfinderCore

/// What the screens show of the session (copied out of the pipeline queue after every change).
struct SessionSnapshot: Sendable {
    var state: GuidanceState = .choosingBuilding
    var statusText = ""
    var places: PlaceList?
    var startPending = false
}

/// Owns `PhonePipeline` (the GuidanceSession and its WayfinderPipeline) and the walk recorder on one serial
/// queue, off the main queue, so the 30-60 Hz frames never wait for the UI and the UI never waits for a
/// detection. Every frame handed to `process` is processed (the motion update runs on all of them); the
/// SensorHub's FrameScheduler decided which ones carry an image. Results go to the main queue.
/// `@unchecked Sendable`: every mutable member is touched only on `queue`.
final class PipelineWorker: @unchecked Sendable {
    private let queue = DispatchQueue(label: "org.wayfinder.pipeline", qos: .userInitiated)
    private let phone: PhonePipeline = {
        var base = PipelineOptions()
        // Placard legends: Vision on the phone (the iOS detector library has no tesseract).
        base.legendReader = { image, corners in VisionLegendReader.read(image: image, cornersRaw: corners) }
        return PhonePipeline(baseOptions: base)
    }()
    private var recorder: WalkRecorder?
    private var recordingURL: URL?

    /// Main queue: guidance commands to render, the new snapshot, and whether the commands answer the
    /// traveler's request ("Where am I", "Repeat": spoken even while guidance speech is paused).
    var onOutput: (@MainActor @Sendable ([GuidanceCommand], SessionSnapshot, Bool) -> Void)?
    /// Main queue: a start that failed (unknown place, model missing), with its message.
    var onStartFailed: (@MainActor @Sendable (String) -> Void)?
    /// Main queue: the bundle folder of a finished recording.
    var onRecordingFinished: (@MainActor @Sendable (URL) -> Void)?

    /// Runs `body` on the pipeline queue with the session, then publishes the snapshot and commands.
    func perform(requested: Bool = false, _ body: @escaping @Sendable (PhonePipeline) -> [GuidanceCommand]) {
        queue.async { [self] in
            let commands = body(phone)
            publish(commands, requested: requested)
        }
    }

    /// Settings for the next start (carry, phrasing...).
    func apply(settings: AppSettings) { queue.async { [self] in phone.settings = settings } }

    /// Starts guidance at the next posed frame, recording if asked.
    func requestStart(recording: Bool, device: String, appVersion: String) {
        queue.async { [self] in
            do { try phone.requestStart() } catch {
                let message = "\(error)"
                DispatchQueue.main.async { [onStartFailed] in MainActor.assumeIsolated { onStartFailed?(message) } }
                return
            }
            if recording, let building = phone.session.building { startRecording(building: building, device: device, appVersion: appVersion) }
            publish([])
        }
    }

    /// Stops guidance and the recording.
    func stop() {
        queue.async { [self] in
            let commands = phone.stop()
            finishRecording()
            publish(commands)
        }
    }

    /// One frame. `done` is called on the pipeline queue with the processing time in seconds (for the
    /// frame scheduler's time budget).
    func process(_ frame: PipelineFrame, meanLuma: Double?, jpeg: Data?, done: @escaping @Sendable (Double) -> Void) {
        queue.async { [self] in
            let start = DispatchTime.now().uptimeNanoseconds
            try? recorder?.append(frame: frame, jpeg: jpeg)
            var commands: [GuidanceCommand] = []
            do { commands = try phone.process(frame, meanLuma: meanLuma) } catch {
                let message = "\(error)"
                DispatchQueue.main.async { [onStartFailed] in MainActor.assumeIsolated { onStartFailed?(message) } }
            }
            done(Double(DispatchTime.now().uptimeNanoseconds - start) / 1e9)
            if commands.contains(.stopSensors) { finishRecording() }
            if !commands.isEmpty { publish(commands) }
        }
    }

    /// Marks a surveyed spot in the recording (the walker stands at this place now); `reply` on the main
    /// queue with nil or the problem. Two or more marks give the bundle a truth.jsonl for `wayfinder eval`.
    func mark(placeId: String, reply: @escaping @MainActor @Sendable (String?) -> Void) {
        queue.async { [self] in
            var problem: String?
            if let recorder, let (poi, floorId) = phone.session.building?.pointOfInterest(idOrName: placeId) {
                do { try recorder.mark(placeId: poi.id, floorId: floorId, x: poi.position.x, y: poi.position.y) } catch { problem = "\(error)" }
            } else {
                problem = "not recording"
            }
            let result = problem
            DispatchQueue.main.async { MainActor.assumeIsolated { reply(result) } }
        }
    }

    /// Plane-anchor events, scored at the next frame (and recorded).
    func ingest(planes: [PlaneRecord]) {
        queue.async { [self] in
            phone.ingest(planes: planes)
            recorder?.append(planes: planes)
        }
    }

    private func startRecording(building: Building, device: String, appVersion: String) {
        let documents = FileManager.default.urls(for: .documentDirectory, in: .userDomainMask)[0]
        let url = documents.appendingPathComponent(WalkRecorder.folderName(for: Date()))
        let s = phone.session
        recorder = try? WalkRecorder(directory: url, building: building, floorId: s.floorId, startId: s.startId,
                                     destinationId: s.destinationId, device: device, appVersion: appVersion,
                                     carry: phone.settings.carry)
        recordingURL = recorder == nil ? nil : url
    }

    private func finishRecording() {
        guard let r = recorder else { return }
        if let problem = r.writeSurveyedTruth() { NSLog("Wayfinder: %@", problem) }
        try? r.close()
        recorder = nil
        if let url = recordingURL {
            DispatchQueue.main.async { [onRecordingFinished] in MainActor.assumeIsolated { onRecordingFinished?(url) } }
        }
        recordingURL = nil
    }

    private func publish(_ commands: [GuidanceCommand], requested: Bool = false) {
        let s = phone.session
        let snapshot = SessionSnapshot(state: s.state, statusText: s.statusText, places: s.places, startPending: phone.startPending)
        DispatchQueue.main.async { [onOutput] in MainActor.assumeIsolated { onOutput?(commands, snapshot, requested) } }
    }
}
#endif
