import Foundation
import Maps
import Navigation
import SessionFormat

/// Where the traveler is in the app's flow.
public enum GuidanceState: String, Sendable, Equatable {
    /// No building chosen yet.
    case choosingBuilding
    /// Building chosen; choose a start place or "I don't know where I am".
    case choosingStart
    /// Choose the destination.
    case choosingDestination
    /// Everything chosen; waiting for Start.
    case ready
    /// Guidance running (until localized, the pipeline gives the exploratory guidance while unsure).
    case guiding
    /// The navigator announced arrival.
    case arrived
}

/// What the session asks the platform layer to do. The iOS shell renders these (VoiceOver or the speech
/// synthesizer, Core Haptics, ARSession); the command line prints them. Logic never speaks directly.
public enum GuidanceCommand: Sendable, Equatable {
    /// Speak a phrase; `interrupt` cuts off what is being said.
    case speak(String, interrupt: Bool)
    /// Play a haptic pattern (the `HapticPattern` name from Navigation).
    case haptic(String)
    /// Start camera, motion and altitude sensors.
    case startSensors
    /// Stop them.
    case stopSensors
}

/// The app's flow as a small state machine (events in, commands out), shared by the SwiftUI screens and
/// tests: choose building, start ("I don't know where I am" = floor only) and destination, then guide.
/// Owns the pipeline while guiding. Not thread-safe: call from one queue.
public final class GuidanceSession {
    /// Current step.
    public private(set) var state: GuidanceState = .choosingBuilding
    /// The chosen building.
    public private(set) var building: Building?
    /// Floor for an unknown start.
    public private(set) var floorId: String?
    /// Chosen start place id (nil = unknown).
    public private(set) var startId: String?
    /// Chosen destination place id.
    public private(set) var destinationId: String?
    /// A short status line, shown and exposed to VoiceOver ("Locating. Keep walking.", "On route."), from
    /// the phrase book of `pipelineOptions.navigator.phrasing.language`.
    public var statusText: String { phrases.phrase(statusKey) }
    /// The places of the chosen building, for the pickers.
    public private(set) var places: PlaceList?

    private var pipeline: WayfinderPipeline?
    private var prompts = TrackingPromptPolicy()
    private var wasLocalized = false
    private var arrivedAtT: Double?
    /// Longest time the pipeline keeps running after arrival for the arrival phrase to be spoken, seconds.
    static let arrivalDrainSeconds = 5.0
    /// Pipeline options used when guidance starts (detector, seeds, the phrasing of guidance). Its phrasing
    /// language also chooses the words of the status and the tracking prompts.
    public var pipelineOptions = PipelineOptions()
    private var cachedPhrases: PhraseBook = .english
    private var statusKey = "status.chooseBuilding"

    /// The app's own words (status lines, tracking prompts, "Guidance stopped"): the phrase book of the
    /// phrasing language (English when it has no file).
    public var phrases: PhraseBook {
        let language = pipelineOptions.navigator.phrasing.language
        if cachedPhrases.language != language {
            cachedPhrases = (try? PhraseBook.load(language: language)) ?? .english
        }
        return cachedPhrases
    }

    /// Creates a session at the first step.
    public init() {}

    private func setStatus(_ key: String) { statusKey = key }

    /// Chooses the building (from the bundled maps or a file opened from Files).
    public func selectBuilding(_ building: Building) {
        self.building = building
        places = PlaceList(building: building)
        floorId = building.floors.first?.id
        startId = nil
        destinationId = nil
        state = .choosingStart
        setStatus("status.chooseStart")
    }

    /// Chooses the floor used when the start is unknown.
    public func selectFloor(_ floorId: String) {
        guard building?.floor(id: floorId) != nil else { return }
        self.floorId = floorId
    }

    /// Chooses the start place, or nil for "I don't know where I am" (floor only).
    public func selectStart(_ placeId: String?) {
        guard state == .choosingStart || state == .choosingDestination || state == .ready else { return }
        startId = placeId
        if let placeId, let floor = building?.floor(ofPointOfInterest: placeId) { floorId = floor.id }
        state = .choosingDestination
        setStatus("status.chooseDestination")
    }

    /// Chooses the destination.
    public func selectDestination(_ placeId: String) {
        guard state == .choosingDestination || state == .ready, building?.pointOfInterest(id: placeId) != nil else { return }
        destinationId = placeId
        state = .ready
        setStatus("status.ready")
    }

    /// Starts guidance: builds the pipeline (localizer from the start prior, navigator to the destination).
    public func start() throws -> [GuidanceCommand] {
        guard state == .ready, let building, let destinationId else {
            throw PipelineError.invalidConfiguration("choose a building, a start and a destination first")
        }
        var options = pipelineOptions
        options.floorId = floorId
        options.startPointOfInterestId = startId
        options.destinationId = destinationId
        pipeline = try WayfinderPipeline(building: building, options: options, imagesAvailable: true)
        prompts = TrackingPromptPolicy(phrases: phrases)
        wasLocalized = false
        state = .guiding
        setStatus("status.locating")
        return [.startSensors]
    }

    /// Stops guidance and the sensors.
    public func stop() -> [GuidanceCommand] {
        guard pipeline != nil else { return [] }
        pipeline = nil
        state = destinationId == nil ? .choosingDestination : .ready
        setStatus("status.stopped")
        return [.stopSensors, .speak(statusText, interrupt: true)]
    }

    /// Forwards ARKit plane-anchor events to the pipeline while guiding (scored at the next frame).
    public func ingest(planes: [PlaneRecord]) { pipeline?.ingest(planes: planes) }

    /// Feeds one camera frame while guiding; returns what to say and play.
    public func process(_ frame: PipelineFrame, meanLuma: Double? = nil) -> [GuidanceCommand] {
        guard let pipeline, state == .guiding || state == .arrived else { return [] }
        let update = pipeline.process(frame)
        var commands = update.events.map(Self.command(of:))
        if state == .arrived {
            // After arrival the pipeline runs on until the arrival phrase is out (it can wait behind a cue
            // still being spoken), at most `arrivalDrainSeconds`; then the sensors stop.
            if commands.contains(where: { if case .speak = $0 { return true } else { return false } })
                || frame.t - (arrivedAtT ?? frame.t) >= Self.arrivalDrainSeconds {
                commands.append(.stopSensors)
                self.pipeline = nil
            }
            return commands
        }
        if let prompt = prompts.update(t: frame.t, state: frame.cameraPose == nil ? .notAvailable : frame.tracking,
                                       reason: frame.trackingReason, meanLuma: meanLuma) {
            commands.append(.speak(prompt, interrupt: false))
        }
        if update.estimate.isLocalized != wasLocalized {
            wasLocalized = update.estimate.isLocalized
            setStatus(wasLocalized ? "status.onRoute" : "status.unsure")
        }
        if pipeline.hasArrived {
            state = .arrived
            setStatus("status.arrived")
            arrivedAtT = frame.t
            if commands.contains(where: { if case .speak = $0 { return true } else { return false } }) {
                commands.append(.stopSensors)
                self.pipeline = nil
            }
        }
        return commands
    }

    /// "Where am I?"
    public func whereAmI(t: Double) -> [GuidanceCommand] {
        guard let pipeline else { return [.speak(statusText, interrupt: true)] }
        let events = pipeline.whereAmI(t: t)
        return events.isEmpty ? [.speak(statusText, interrupt: true)] : events.map(Self.command(of:))
    }

    /// "Repeat" the last instruction.
    public func repeatLast(t: Double) -> [GuidanceCommand] {
        guard let pipeline else { return [.speak(statusText, interrupt: true)] }
        let events = pipeline.repeatLast(t: t)
        return events.isEmpty ? [.speak(statusText, interrupt: true)] : events.map(Self.command(of:))
    }

    static func command(of event: TimedGuidanceEvent) -> GuidanceCommand {
        switch event.event {
        case .speak(let text, _, let interrupt): return .speak(text, interrupt: interrupt)
        case .haptic(let pattern): return .haptic("\(pattern)")
        }
    }
}
