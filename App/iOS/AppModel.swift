#if canImport(SwiftUI) && canImport(ARKit) && canImport(AVFoundation) && os(iOS)
import ARKit
import AVFoundation
import Maps
import Navigation
import SwiftUI
import WayfinderCore

/// SwiftUI's observable face of the shared logic. Every decision is made in WayfinderCore (tested on
/// Linux): the flow and the pipeline (`PhonePipeline` on the `PipelineWorker`'s queue), camera health
/// (`SessionHealth`), speech (`SpeechQueue` in `SpeechOutput`), haptics (`HapticCue`), eyes-free commands
/// (`EyesFreeCommandMap`), screen wake (`ScreenWakePolicy`), settings (`AppSettings`) and the onboarding
/// (`OrientationCoach`). This class forwards events and renders commands on the main actor.
@MainActor
final class AppModel: ObservableObject {
    @Published private(set) var snapshot = SessionSnapshot()
    @Published private(set) var healthStatus: String?
    @Published private(set) var offerSettingsLink = false
    @Published var lastError: String?
    @Published private(set) var lastBundleURL: URL?
    @Published var settings: AppSettings { didSet { settingsChanged(from: oldValue) } }

    let worker = PipelineWorker()
    let sensors: SensorHub
    let speech: SpeechOutput
    let haptics = HapticsOutput()
    let remote = RemoteCommands()
    private(set) var phrases: PhonePhrases
    private var health: SessionHealth
    private var turns: TurnCueResolver?
    private var wake = ScreenWakePolicy()
    private var tickTimer: Timer?
    private var sensorsRunning = false

    /// What the status line shows: the camera's trouble when there is one, else the session's status.
    var statusText: String { healthStatus ?? snapshot.statusText }
    var state: GuidanceState { snapshot.state }
    var guiding: Bool { snapshot.state == .guiding || snapshot.startPending }

    init() {
        let settings = SettingsStore.load()
        let phrases = (try? PhonePhrases.load(language: settings.phrasing.language)) ?? (try? PhonePhrases.load(language: "en"))
        // en.json ships in the bundle (project.yml); without it nothing can be said, which is a build error.
        self.phrases = phrases!
        self.settings = settings
        health = SessionHealth(phrases: self.phrases, carry: settings.carry)
        turns = (try? PhraseBook.load(language: settings.phrasing.language)).map(TurnCueResolver.init(phrases:))
        sensors = SensorHub(worker: worker)
        speech = SpeechOutput(outputLostText: self.phrases.text(.headphonesGone))
        speech.apply(settings: settings)
        haptics.enabled = settings.hapticsEnabled
        worker.apply(settings: settings)
        worker.onOutput = { [weak self] commands, snapshot, requested in self?.received(commands, snapshot, requested: requested) }
        worker.onStartFailed = { [weak self] message in self?.startFailed(message) }
        worker.onRecordingFinished = { [weak self] url in self?.lastBundleURL = url }
        sensors.onHealth = { [weak self] event in self?.handleHealth(event) }
        remote.onInput = { [weak self] input in self?.handle(input) }
    }

    /// Bundled buildings (Maps/Buildings in the app bundle).
    var bundledBuildings: [Building] { BundledMapsLoader.all() }

    func select(building: Building) { worker.perform { $0.session.selectBuilding(building); return [] } }
    func selectStart(_ id: String?) { worker.perform { $0.session.selectStart(id); return [] } }
    func selectDestination(_ id: String) { worker.perform { $0.session.selectDestination(id); return [] } }

    /// Start pressed: the camera permission is checked first (SessionHealth).
    func startGuidance() {
        let auth: CameraAuthorization
        switch AVCaptureDevice.authorizationStatus(for: .video) {
        case .authorized: auth = .authorized
        case .denied: auth = .denied
        case .restricted: auth = .restricted
        default: auth = .notDetermined
        }
        handleHealth(.startRequested(auth))
    }

    func stopGuidance() {
        worker.stop()
        stopSensors()
    }

    /// Eyes-free inputs (Magic Tap, headphone buttons, the two big buttons).
    func handle(_ input: EyesFreeInput) {
        switch EyesFreeCommandMap.action(for: input, speaking: speech.isSpeaking, speechPaused: speech.isPaused, guiding: guiding) {
        case .repeatLast:
            let t = CACurrentMediaTime()
            worker.perform(requested: true) { $0.session.repeatLast(t: t) }
        case .whereAmI:
            let t = CACurrentMediaTime()
            worker.perform(requested: true) { $0.session.whereAmI(t: t) }
        case .silence: speech.silence()
        case .pauseSpeech:
            speech.pause()
            speech.speak(phrases.text(.paused), interrupt: true, requested: true)
        case .resumeSpeech:
            speech.resume()
            speech.speak(phrases.text(.resumed), interrupt: true, requested: true)
        case .none: break
        }
    }

    /// Marks that the phone is at this place now (surveyed truth for `wayfinder eval`, docs/ios.md).
    func markSurveyedSpot(_ placeId: String) {
        worker.mark(placeId: placeId) { [weak self] problem in
            if let problem { self?.lastError = problem }
        }
    }

    /// True while a walk is being recorded.
    var recordingWalk: Bool { sensorsRunning && settings.recordWalks }

    func whereAmI() { handle(.whereAmIButton) }
    func repeatLast() { handle(.repeatButton) }

    func openSettingsApp() {
        if let url = URL(string: UIApplication.openSettingsURLString) { UIApplication.shared.open(url) }
    }

    // MARK: rendering

    private func received(_ commands: [GuidanceCommand], _ snapshot: SessionSnapshot, requested: Bool) {
        self.snapshot = snapshot
        let cues = turns?.cues(of: commands) ?? commands.compactMap { c in
            if case .haptic(let name) = c { return HapticCue(patternName: name) } else { return nil }
        }
        cues.forEach(haptics.play)
        for c in commands {
            switch c {
            case .speak(let text, let interrupt): speech.speak(text, interrupt: interrupt || requested, requested: requested)
            case .haptic: break
            case .startSensors: break   // started with the permission check (beginGuidance)
            case .stopSensors: stopSensors()
            }
        }
        updateWake()
    }

    private func handleHealth(_ event: HealthEvent) {
        for command in health.handle(event) {
            switch command {
            case .requestCameraPermission:
                AVCaptureDevice.requestAccess(for: .video) { [weak self] granted in
                    DispatchQueue.main.async { MainActor.assumeIsolated { self?.handleHealth(.permissionAnswered(granted: granted)) } }
                }
            case .beginGuidance: beginGuidance()
            case .endGuidance: stopGuidance()
            case .speak(let text, let interrupt): speech.speak(text, interrupt: interrupt, requested: true)
            case .status(let text): healthStatus = text
            case .offerSettings(let offer): offerSettingsLink = offer
            case .restartTracking: sensors.restartTracking()
            }
        }
    }

    private func beginGuidance() {
        let version = Bundle.main.object(forInfoDictionaryKey: "CFBundleShortVersionString") as? String ?? "0"
        sensors.configure(recording: settings.recordWalks, settings: settings, sightingSource: PipelineOptions().sightingSource)
        worker.apply(settings: settings)
        worker.requestStart(recording: settings.recordWalks, device: UIDevice.current.model, appVersion: version)
        sensors.start()
        sensorsRunning = true
        remote.enable(title: "Wayfinder guidance")
        tickTimer?.invalidate()
        tickTimer = Timer.scheduledTimer(withTimeInterval: 1, repeats: true) { [weak self] _ in
            MainActor.assumeIsolated { self?.handleHealth(.tick(t: CACurrentMediaTime())) }
        }
        updateWake(forceGuiding: true)
    }

    private func stopSensors() {
        guard sensorsRunning else { return }
        sensorsRunning = false
        sensors.statistics { stats in
            NSLog("Wayfinder frames: %ld arrived, %ld processed (%.1f Hz), %ld detected (%.1f Hz), max backlog %ld, pipeline %.0f %% of a core",
                  stats.arrived, stats.processed, stats.processedHz, stats.detected, stats.detectedHz, stats.maxBacklog, 100 * stats.coreShare)
        }
        sensors.stop()
        tickTimer?.invalidate()
        tickTimer = nil
        remote.disable()
        handleHealth(.stopped)
        updateWake(forceGuiding: false)
    }

    private func startFailed(_ message: String) {
        lastError = message
        speech.speak(message, interrupt: true, requested: true)
        stopSensors()
    }

    private func updateWake(forceGuiding: Bool? = nil) {
        if let value = wake.update(guiding: forceGuiding ?? (sensorsRunning || guiding), recording: sensorsRunning && settings.recordWalks) {
            UIApplication.shared.isIdleTimerDisabled = value
        }
    }

    private func settingsChanged(from old: AppSettings) {
        let s = settings.sanitized()
        SettingsStore.save(s)
        speech.apply(settings: s)
        haptics.enabled = s.hapticsEnabled
        health.carry = s.carry
        worker.apply(settings: s)
        if s.phrasing.language != old.phrasing.language, let p = try? PhonePhrases.load(language: s.phrasing.language) {
            phrases = p
            turns = (try? PhraseBook.load(language: s.phrasing.language)).map(TurnCueResolver.init(phrases:))
        }
    }
}
#endif
