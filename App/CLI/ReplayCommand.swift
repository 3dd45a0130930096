import Foundation
import Maps
import Navigation
import SessionFormat
import WayfinderCore

/// `wayfinder replay`: runs a recorded session through exactly the phone's pipeline and prints the
/// timestamped announcements.
enum ReplayCommand: Subcommand {
    static let name = "replay"
    static let summary = "replay a recorded walk through the pipeline and print the spoken directions"
    static let usage = """
    Usage: wayfinder replay BUNDLE --map MAP [--to DEST] [--from START] [--floor FLOOR]
                            [--detector recorded|cascade|unet|auto] [--models DIR] [--seed N] [--trace OUT.jsonl]
                            [--no-compass] [--no-planes] [--no-north-check] [--param NAME=V]
                            [--speak] [--audio OUT.wav] [--espeak PATH]
                            [--units meters|feet|steps] [--stride M] [--clock-face] [--verbosity brief|normal|detailed]
                            [--language LANG]

    Replays the recorded-session bundle BUNDLE (frames.jsonl, observations.jsonl or images) on the building
    MAP and prints each announcement as "[  12.3 s] text" (haptics as "[  12.3 s] (haptic: pattern)", the
    phone's tracking prompts as "[  12.3 s] Slow down (tracking prompt)"). \(MapSpec.usageLine).
      --to DEST        destination point-of-interest id or name (default: session.json's destination)
      --from START     start point-of-interest id or name (default: session.json's start; none = floor only)
      --floor FLOOR    start floor id when the start is unknown (default: session.json's floor)
      --seed N         particle filter seed (default 1)
      --trace FILE     write one JSON line per frame: t, x, y, floorId, headingRad, confidence, localized,
                       hypotheses, sightings, announcements, haptics; sightingList (kind, rangeMeters,
                       bearingRad, score, text) on frames with sightings; tracking and trackingPrompt when
                       tracking is not normal; while not localized also advice
                       (the exploratory instruction in force) and spokenAdvice (when one is said);
                       hypothesisList (weight, x, y, headingRad, evidenceNats, positionStdMeters,
                       headingStdRad) while not
                       localized or while more than one hypothesis is held; sightingsUnexplained (true) while
                       the dominant hypothesis leaves the recent sightings unexplained
      --trace-particles FILE
                       write the particle cloud (an even subsample) every --trace-particles-every seconds, one
                       JSON line per moment: {"t": s, "count": n, "columns": ["xMeters", "yMeters", "headingRad",
                       "scale", "weight", "floorId"], "particles": [[x, y, heading, scale, weight, floor], ...]};
                       heading is the camera's in the map (VIO yaw + the particle's yaw offset), weight is
                       normalised over the whole cloud, not over the subsample
      --trace-particles-every S
                       seconds between particle dumps (default 0.5; the last frame is always dumped)
      --trace-particles-count N
                       particles per dump, at most (default 5000)
    \(EvidenceSwitches.usage)
    Speech (espeak-ng, Debian package espeak-ng, installed by scripts/setup.sh):
      --speak          after the replay, play the walk in real time: each announcement is printed and spoken
                       (espeak-ng on the default audio device) when it happened; a later one cuts off one
                       still playing, as on the phone
      --audio OUT.wav  write the walk's sound on its own timeline: every utterance (espeak-ng, 22050 Hz,
                       16-bit mono) and a short tick pattern per haptic (turnCue: two high ticks; wrongWay:
                       three low buzzes; offRoute: one long buzz; arrived: three rising ticks)
      --espeak PATH    the espeak-ng executable (default: espeak-ng on PATH)
    Phrasing (what the traveler hears; the same options as the app's settings):
      --units U        meters (default), feet, or steps of --stride meters (default 0.7 m; measure the
                       walker's own: distance walked / steps counted)
      --clock-face     directions with the clock face too ("Turn right now, toward 3 o'clock.")
      --verbosity V    brief (cues and arrival), normal (default; plus alerts and continuations), detailed
                       (plus "Continue N meters" after every turn)
      --language LANG  phrase book Navigation/Locales/LANG.json, e.g. en (default), es
    Warnings (stderr, the replay goes on): session.json's mapId naming another building than MAP, observations
    of sign kinds MAP lacks (ignored), over 64 observations on one frame (highest scores kept), missing images.
    Exit codes: 0 ok, 1 bad input (map, bundle), 2 usage.
    """

    /// One JSON line per particle cloud for `--trace-particles`: time, particle count and one row per particle
    /// (x and y in meters to the millimetre, camera heading in radians, VIO scale, normalised weight, floor id).
    static func particleTraceLines(_ timeline: [ParticleSnapshot]) -> [String] {
        timeline.map { snap in
            let rows = snap.particles.map { p -> String in
                let floor = String(data: (try? JSONEncoder().encode(p.floorId)) ?? Data("\"\"".utf8), encoding: .utf8) ?? "\"\""
                return String(format: "[%.3f,%.3f,%.4f,%.4f,%.6g,", p.position.x, p.position.y, p.headingRad, p.scale, p.weight)
                    + floor + "]"
            }
            return String(format: "{\"t\":%.4f,\"count\":%d,", snap.t, snap.particles.count)
                + "\"columns\":[\"xMeters\",\"yMeters\",\"headingRad\",\"scale\",\"weight\",\"floorId\"],"
                + "\"particles\":[" + rows.joined(separator: ",") + "]}"
        }
    }

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let mapPath = try arguments.requiredOption("map")
        var pipeline = PipelineOptions()
        try EvidenceSwitches.apply(&arguments, to: &pipeline)
        let to = try arguments.option("to"), from = try arguments.option("from")
        pipeline.floorId = try arguments.option("floor") ?? MapSpec.floor(of: mapPath)
        if let seed = try arguments.seedOption() { pipeline.seed = seed }
        let tracePath = try arguments.option("trace")
        let particleTracePath = try arguments.option("trace-particles")
        let particleTraceEverySeconds = try arguments.doubleOption("trace-particles-every") ?? 0.5
        let particleTraceCount = try arguments.intOption("trace-particles-count") ?? 5000
        guard particleTraceEverySeconds > 0 else { throw CLIError.usage("--trace-particles-every must be > 0") }
        guard particleTraceCount > 0 else { throw CLIError.usage("--trace-particles-count must be > 0") }
        let speak = arguments.flag("speak")
        let audioPath = try arguments.option("audio")
        let espeakPath = try arguments.option("espeak")
        pipeline.navigator.phrasing = try phrasingOptions(&arguments)
        let positionals = try arguments.positionals()
        guard positionals.count == 1 else { throw CLIError.usage("expected one BUNDLE directory (see --help)") }

        // Find the synthesizer before the (long) replay: a missing espeak-ng is said at once.
        var synthesizer: EspeakSynthesizer? = nil
        if speak || audioPath != nil {
            do {
                synthesizer = try EspeakSynthesizer(voice: pipeline.navigator.phrasing.language, name: espeakPath ?? "espeak-ng")
            } catch {
                throw CLIError.failure("\(speak ? "--speak" : "--audio"): \(error)")
            }
        }
        let building = try loadMap(mapPath)
        pipeline.destinationId = try to.map { try resolvePlace($0, flag: "--to", in: building, mapSpec: mapPath) }
        pipeline.startPointOfInterestId = try from.map { try resolvePlace($0, flag: "--from", in: building, mapSpec: mapPath) }
        let bundle = try loadBundle(positionals[0])
        for w in bundle.warnings { note("warning: \(w)") }
        if [.cascade, .unet].contains(pipeline.sightingSource),
           !bundle.frames.contains(where: { bundle.presentImageURL(for: $0) != nil }) {
            note("warning: --detector \(pipeline.sightingSource.rawValue) but \(positionals[0]) has no images: no sign sightings")
        }
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: pipeline))
        options.snapshotParticleCount = 0
        if particleTracePath != nil {
            options.particleTimelineIntervalSeconds = particleTraceEverySeconds
            options.particleTimelineCount = particleTraceCount
        }
        let result: ReplayResult
        do {
            result = try Replay.run(bundle: bundle, building: building, options: options) { fraction in
                progress(String(format: "replay: %3.0f%%", fraction * 100))
            }
        } catch {
            throw CLIError.failure("\(positionals[0]): \(error)")
        }
        for w in result.warnings.prefix(20) { note("warning: \(w)") }
        if result.warnings.count > 20 { note("warning: ... \(result.warnings.count - 20) more") }

        var lines: [(Double, String)] = result.announcements.map { ($0.t, $0.text) }
        lines += result.haptics.map { ($0.t, "(haptic: \($0.pattern))") }
        lines += result.trackingPrompts.map { ($0.t, "\($0.text) (tracking prompt)") }
        lines = lines.enumerated().sorted { ($0.element.0, $0.offset) < ($1.element.0, $1.offset) }.map(\.element)
        let startT = result.trace.first?.t ?? 0, endT = result.trace.last?.t ?? 0
        if speak, let synthesizer {
            try speakInRealTime(result, startT: startT, synthesizer: synthesizer)
        } else {
            for (t, text) in lines { print(String(format: "[%7.1f s] ", t) + text) }
        }
        if let audioPath, let synthesizer {
            do {
                // The walk's length plus the tail of the last utterance.
                let audio = try WalkAudioRenderer.render(announcements: result.announcements, haptics: result.haptics,
                                                         startT: startT, endT: endT, synthesizer: synthesizer)
                try WAVFile.write(audio, to: URL(fileURLWithPath: audioPath))
                note(String(format: "replay: audio written to %@ (%.1f s, %d utterances, %d haptics)", audioPath,
                                audio.durationSeconds, result.announcements.count, result.haptics.count))
            } catch let e as SpeechError {
                throw CLIError.failure("--audio: \(e)")
            } catch {
                throw CLIError.failure("cannot write audio \(audioPath): \(error.localizedDescription)")
            }
        }

        if let tracePath {
            let encoder = JSONEncoder()
            encoder.outputFormatting = [.sortedKeys]
            var data = Data()
            for record in result.trace {
                data.append(try encoder.encode(record))
                data.append(0x0A)
            }
            do { try data.write(to: URL(fileURLWithPath: tracePath), options: .atomic) } catch {
                throw CLIError.failure("cannot write trace \(tracePath): \(error.localizedDescription)")
            }
            note("replay: trace written to \(tracePath) (\(result.trace.count) lines)")
        }
        if let particleTracePath {
            let text = particleTraceLines(result.particleTimeline).joined(separator: "\n") + "\n"
            do { try Data(text.utf8).write(to: URL(fileURLWithPath: particleTracePath), options: .atomic) } catch {
                throw CLIError.failure("cannot write particle trace \(particleTracePath): \(error.localizedDescription)")
            }
            note("replay: particle trace written to \(particleTracePath) (\(result.particleTimeline.count) lines)")
        }
        return 0
    }
}

/// Reads the phrasing flags (--units, --stride, --clock-face, --verbosity, --language) into options;
/// a bad value is a usage error naming the flag and the accepted values.
func phrasingOptions(_ arguments: inout ArgumentList) throws -> PhrasingOptions {
    var o = PhrasingOptions()
    if let u = try arguments.option("units") {
        guard let unit = DistanceUnit(rawValue: u) else { throw CLIError.usage("--units must be meters, feet or steps (got '\(u)')") }
        o.distanceUnit = unit
    }
    if let stride = try arguments.doubleOption("stride") {
        guard stride.isFinite, stride >= 0.2, stride <= 1.5 else {
            throw CLIError.usage("--stride must be a step length in meters between 0.2 and 1.5 (got \(stride))")
        }
        o.strideMeters = stride
    }
    if arguments.flag("clock-face") { o.directionStyle = .clockFace }
    if let v = try arguments.option("verbosity") {
        guard let verbosity = Verbosity(rawValue: v) else {
            throw CLIError.usage("--verbosity must be brief, normal or detailed (got '\(v)')")
        }
        o.verbosity = verbosity
    }
    if let language = try arguments.option("language") {
        do { _ = try PhraseBook.load(language: language) } catch {
            throw CLIError.usage("--language \(language): \(error)")
        }
        o.language = language
    }
    return o
}

/// Plays the replayed walk in real time: each announcement and haptic is printed at its time on the walk's
/// clock (from `startT`), and each announcement is spoken; a later utterance stops one still playing.
func speakInRealTime(_ result: ReplayResult, startT: Double, synthesizer: EspeakSynthesizer) throws {
    enum Item { case say(String), feel(String) }
    var items: [(t: Double, item: Item)] = result.announcements.map { ($0.t, .say($0.text)) }
    items += result.haptics.map { ($0.t, .feel($0.pattern)) }
    items += result.trackingPrompts.map { ($0.t, .say($0.text)) }  // what the phone would say, too
    items = items.enumerated().sorted { ($0.element.t, $0.offset) < ($1.element.t, $1.offset) }.map(\.element)
    // Unbuffered, so each line appears when it is spoken.
    func say(_ line: String) { FileHandle.standardOutput.write(Data((line + "\n").utf8)) }
    let clock = Date()
    var playing: Process? = nil
    var warned = false
    /// Waits for an utterance to end; espeak-ng's complaints (no sound device) are shown once, not per line.
    func finish(_ p: Process) {
        p.waitUntilExit()
        guard let pipe = p.standardError as? Pipe else { return }
        let text = String(decoding: pipe.fileHandleForReading.readDataToEndOfFile(), as: UTF8.self)
        guard !warned, let line = text.split(separator: "\n").first else { return }
        warned = true
        note("warning: espeak-ng could not play the speech: \(line) (no sound device? --audio OUT.wav writes the walk's sound to a file)")
    }
    for (t, item) in items {
        let wait = (t - startT) - Date().timeIntervalSince(clock)
        if wait > 0 { Thread.sleep(forTimeInterval: wait) }
        switch item {
        case .say(let text):
            say(String(format: "[%7.1f s] ", t) + text)
            if let p = playing {
                if p.isRunning { p.terminate() }
                finish(p)
            }
            do { playing = try synthesizer.speak(text) } catch { throw CLIError.failure("--speak: \(error)") }
        case .feel(let pattern):
            say(String(format: "[%7.1f s] ", t) + "(haptic: \(pattern))")
        }
    }
    if let p = playing { finish(p) }
}

/// Reads a recorded-session bundle, turning errors into CLI failures that name the file and line.
func loadBundle(_ path: String) throws -> SessionBundle {
    do { return try SessionBundle.read(from: URL(fileURLWithPath: path)) } catch {
        throw CLIError.failure("\(error)")
    }
}
