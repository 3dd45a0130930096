import Evaluation
import Foundation
import WayfinderCore

/// `wayfinder render`: the trainer's view of a walk, an HTML page with a playhead (and a PNG of it).
enum RenderCommand: Subcommand {
    static let name = "render"
    static let summary = "the trainer's view of a walk: a page with a playhead over positions, particles, speech, sightings"
    static let usage = """
    Usage: wayfinder render BUNDLE --map MAP -o WALK.html [--png WALK.png] [--at T1,T2,...] [--from START]
                            [--to DEST] [--seed N] [--cloud-interval S]

    Replays BUNDLE through the pipeline (with the phone's tracking prompts) and writes one self-contained
    HTML page (nothing fetched): the floor plan with walls, signs and graph, the true path (if truth.jsonl is
    present) and the estimate coloured by error, and a timeline with a playhead to drag, click or play
    (open WALK.html#t=12.5 to start at 12.5 s). At the playhead the plan shows the true and estimated
    positions, the particle cloud and hypotheses, the sightings of the last second with the sign each
    matched, and the route in force; a panel gives the confidence, tracking state, what was said and felt,
    wrong turns and re-routes. The timeline marks lost and limited tracking, announcements, tracking
    prompts, haptics, sightings, wrong-way / off-route corrections and re-routes.
      -o FILE              the HTML page (required)
      --png FILE           also a screenshot of the page at the first convergence, by headless Chromium
      --at T1,T2,...       also keep the particle clouds at these times (seconds; shown with a checkbox,
                           with the start, first convergence, middle and end)
      --from, --to         start and destination place (id or name; default: session.json's)
      --seed N             particle filter seed (default 1)
      --cloud-interval S   seconds between the clouds kept for the playhead (default 0.5, longer for walks
                           over 5 minutes: at most 600 clouds of 150 particles)
    \\(MapSpec.usageLine).
    Warnings (stderr) as for replay, e.g. session.json's mapId naming another building than MAP.
    Exit codes: 0 ok, 1 bad input (map, bundle, places) or the screenshot failed, 2 usage.
    """

    /// Most particle clouds kept for the playhead (each 150 particles, about 2 KB of JSON).
    static let maximumClouds = 600.0

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let mapPath = try arguments.requiredOption("map")
        guard let out = try arguments.option("o") ?? arguments.option("output") else {
            throw CLIError.usage("missing -o WALK.html (the page to write)")
        }
        let png = try arguments.option("png")
        let to = try arguments.option("to"), from = try arguments.option("from")
        var pipeline = PipelineOptions()
        if let seed = try arguments.seedOption() { pipeline.seed = seed }
        let cloudInterval = try arguments.doubleOption("cloud-interval")
        if let cloudInterval, cloudInterval <= 0 { throw CLIError.usage("--cloud-interval must be > 0 seconds") }
        var times: [Double] = []
        if let at = try arguments.option("at") {
            for part in at.split(separator: ",") {
                guard let v = Double(part.trimmingCharacters(in: .whitespaces)), v.isFinite else {
                    throw CLIError.usage("--at takes comma-separated seconds, got '\(part)'")
                }
                times.append(v)
            }
        }
        let positionals = try arguments.positionals()
        guard positionals.count == 1 else { throw CLIError.usage("expected one BUNDLE directory (see --help)") }
        let building = try loadMap(mapPath)
        pipeline.destinationId = try to.map { try resolvePlace($0, flag: "--to", in: building, mapSpec: mapPath) }
        pipeline.startPointOfInterestId = try from.map { try resolvePlace($0, flag: "--from", in: building, mapSpec: mapPath) }
        pipeline.floorId = MapSpec.floor(of: mapPath)
        let bundle = try loadBundle(positionals[0])
        for w in bundle.warnings { note("warning: \(w)") }
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: pipeline))
        options.snapshotTimes = times
        options.snapshotParticleCount = 1200
        let duration = (bundle.frames.last?.t ?? 0) - (bundle.frames.first?.t ?? 0)
        options.particleTimelineIntervalSeconds = cloudInterval ?? max(0.5, duration / Self.maximumClouds)
        let result: ReplayResult
        do {
            result = try Replay.run(bundle: bundle, building: building, options: options) { fraction in
                progress(String(format: "render: replay %3.0f%%", fraction * 100))
            }
        } catch {
            throw CLIError.failure("\(positionals[0]): \(error)")
        }
        for w in result.warnings.prefix(20) { note("warning: \(w)") }
        if result.warnings.count > 20 { note("warning: ... \(result.warnings.count - 20) more") }
        let score: WalkScore? = bundle.truth.isEmpty ? nil : WalkEvaluator.score(
            name: bundle.url.lastPathComponent, result: result, truth: bundle.truth, building: building,
            destination: options.pipeline.destinationId)
        let html = WalkReport.html(title: "Walk \(bundle.url.lastPathComponent)", building: building, result: result,
                                   truth: bundle.truth, score: score)
        let htmlURL = URL(fileURLWithPath: out)
        do { try Data(html.utf8).write(to: htmlURL, options: .atomic) } catch {
            throw CLIError.failure("cannot write \(out): \(error.localizedDescription)")
        }
        note("render: wrote \(out) (\(html.utf8.count / 1024) KB)")
        if let png {
            do { try ChromiumScreenshot.capture(html: htmlURL, png: URL(fileURLWithPath: png), width: 1400, height: 1700) } catch {
                throw CLIError.failure("\(error)")
            }
            note("render: wrote \(png)")
        }
        return 0
    }
}
