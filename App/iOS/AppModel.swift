#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import ARKit
import Maps
import SwiftUI
import WayfinderCore

/// SwiftUI's observable face of `GuidanceSession` (the logic lives in WayfinderCore and is tested on
/// Linux). Renders the session's commands through speech, haptics and the sensor adapters.
@MainActor
final class AppModel: ObservableObject {
    @Published private(set) var state: GuidanceState = .choosingBuilding
    @Published private(set) var statusText = ""
    @Published var recording = false
    @Published var lastError: String?

    let session = GuidanceSession()
    let speech = SpeechOutput()
    let haptics = HapticsOutput()
    let sensors = SensorHub()
    let recorder = WalkRecorderAdapter()

    init() {
        sensors.onFrame = { [weak self] frame, luma, jpeg in self?.handle(frame: frame, meanLuma: luma, jpeg: jpeg) }
        sensors.onPlanes = { [weak self] planes in
            self?.session.ingest(planes: planes)
            self?.recorder.append(planes: planes)
        }
        refresh()
    }

    /// Bundled buildings (Maps/Buildings in the app bundle).
    var bundledBuildings: [Building] { BundledMapsLoader.all() }

    func select(building: Building) { session.selectBuilding(building); refresh() }
    func selectStart(_ id: String?) { session.selectStart(id); refresh() }
    func selectDestination(_ id: String) { session.selectDestination(id); refresh() }

    func startGuidance() {
        do { render(try session.start()) } catch { lastError = "\(error)"; speech.speak("\(error)", interrupt: true) }
        if recording, let building = session.building { recorder.start(building: building, session: session) }
        refresh()
    }

    func stopGuidance() { render(session.stop()); recorder.stop(); refresh() }
    func whereAmI() { render(session.whereAmI(t: CACurrentMediaTime())) }
    func repeatLast() { render(session.repeatLast(t: CACurrentMediaTime())) }

    private func handle(frame: PipelineFrame, meanLuma: Double?, jpeg: Data?) {
        recorder.append(frame: frame, jpeg: jpeg)
        render(session.process(frame, meanLuma: meanLuma))
        refresh()
    }

    private func render(_ commands: [GuidanceCommand]) {
        for c in commands {
            switch c {
            case .speak(let text, let interrupt): speech.speak(text, interrupt: interrupt)
            case .haptic(let pattern): haptics.play(pattern)
            case .startSensors: sensors.start()
            case .stopSensors: sensors.stop()
            }
        }
    }

    private func refresh() { state = session.state; statusText = session.statusText }
}
#endif
