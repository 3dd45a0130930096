import Foundation
import Maps
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
                            [--no-compass] [--no-planes] [--param NAME=V]

    Replays the recorded-session bundle BUNDLE (frames.jsonl, observations.jsonl or images) on the building
    MAP and prints each announcement as "[  12.3 s] text" (haptics as "[  12.3 s] (haptic: pattern)", the
    phone's tracking prompts as "[  12.3 s] Slow down (tracking prompt)"). \(MapSpec.usageLine).
      --to DEST        destination point-of-interest id or name (default: session.json's destination)
      --from START     start point-of-interest id or name (default: session.json's start; none = floor only)
      --floor FLOOR    start floor id when the start is unknown (default: session.json's floor)
      --detector       where sign sightings come from (default auto: the detector on the images when any is
                       present, a frame whose image is missing using its recorded observations; else the
                       recorded observations)
      --models DIR     detector models folder (default SignDetector/models)
      --seed N         particle filter seed (default 1)
      --trace FILE     write one JSON line per frame: t, x, y, floorId, headingRad, confidence, localized,
                       hypotheses, sightings, announcements, haptics; tracking and trackingPrompt when
                       tracking is not normal; while not localized also advice
                       (the exploratory instruction in force) and spokenAdvice (when one is said)
    \(EvidenceSwitches.usage)
    Warnings (stderr, the replay goes on): session.json's mapId naming another building than MAP, observations
    of sign kinds MAP lacks (ignored), over 64 observations on one frame (highest scores kept), missing images.
    Exit codes: 0 ok, 1 bad input (map, bundle), 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let mapPath = try arguments.requiredOption("map")
        var pipeline = PipelineOptions()
        try EvidenceSwitches.apply(&arguments, to: &pipeline)
        let to = try arguments.option("to"), from = try arguments.option("from")
        pipeline.floorId = try arguments.option("floor") ?? MapSpec.floor(of: mapPath)
        pipeline.modelsDirectory = try arguments.option("models")
        if let seed = try arguments.seedOption() { pipeline.seed = seed }
        if let d = try arguments.option("detector") {
            guard let source = SightingSource(rawValue: d == "auto" ? "automatic" : d) else {
                throw CLIError.usage("--detector must be recorded, cascade, unet or auto")
            }
            pipeline.sightingSource = source
        }
        let tracePath = try arguments.option("trace")
        let positionals = try arguments.positionals()
        guard positionals.count == 1 else { throw CLIError.usage("expected one BUNDLE directory (see --help)") }

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
        for (t, text) in lines { print(String(format: "[%7.1f s] ", t) + text) }

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
        return 0
    }
}

/// Reads a recorded-session bundle, turning errors into CLI failures that name the file and line.
func loadBundle(_ path: String) throws -> SessionBundle {
    do { return try SessionBundle.read(from: URL(fileURLWithPath: path)) } catch {
        throw CLIError.failure("\(error)")
    }
}
