import Foundation
import Maps
import SessionFormat
import Simulation

/// `wayfinder simulate`: writes a simulated recorded-session bundle with ground truth (see docs/simulator.md).
enum SimulateCommand: Subcommand {
    static let name = "simulate"
    static let summary = "simulate a walk on a map and write a recorded-session bundle with ground truth"
    static let usage = """
    Usage: wayfinder simulate --from A --to B --seed N -o BUNDLE [--map MAP] [--carry handheld|lanyard]
                              [--orientation portrait|landscape] [--rate HZ] [--detector-rate HZ]
                              [--images] [--image-rate HZ] [--floor-only-start | --known-start]
                              [--tracking-loss T] [--tracking-loss-duration S] [--vio-reset T] [--wrong-turn]
                              [--north-offset DEG] [--tour-minutes M] [--sim-detector NAME] [--sim-params FILE] [--scenario FILE]
                              [--overwrite]

    Simulates a person walking the shortest route from A to B (point-of-interest ids or names, or route-graph
    node ids as the committed scenarios use) with a phone held camera-forward, and writes the bundle (format v1: session.json, frames.jsonl, observations.jsonl,
    truth.jsonl, images/ with --images) to BUNDLE. The same arguments and seed give the same bundle.
      --map MAP            `office` (the default), `skeri:FLOOR` or a map-v1 JSON file (as for every command)
      --scenario FILE      start from a scenario definition (Tests/Scenarios/*.json); flags override it
      --carry              handheld (default) or lanyard
      --orientation        portrait (default) or landscape
      --rate HZ            camera frame rate (default 30)
      --detector-rate HZ   rate of frames with sign observations (default 10)
      --images             also render 640x480 PPM camera images (slow) at --image-rate HZ (default 2)
      --floor-only-start   session.json gives only the start floor (default)
      --known-start        session.json names the start place
      --tracking-loss T    ARKit tracking lost at T seconds for --tracking-loss-duration S (default 4)
      --vio-reset T        full VIO reset at T seconds (new world origin and yaw)
      --wrong-turn         take a wrong branch at one junction, then turn around
      --north-offset DEG   compass reading when facing map north (default: drawn from the seed)
      --tour-minutes M     a long tour: walk A to B and back, again and again, for at least M minutes
      --overwrite          replace an existing bundle at BUNDLE
    \(SimDetectorOption.usage)
    Exit codes: 0 ok, 1 bad input (map, places, scenario), 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        var scenario: SimulationScenario
        let scenarioPath = try arguments.option("scenario")
        let (simulation, _) = try SimDetectorOption.parse(&arguments)
        let mapOption = try arguments.option("map")
        let from = try arguments.option("from"), to = try arguments.option("to")
        let seed = try arguments.option("seed")
        if let path = scenarioPath {
            do { scenario = try SimulationScenario.load(contentsOf: URL(fileURLWithPath: path)) } catch {
                throw CLIError.failure("\(error)")
            }
        } else {
            guard let from, let to else { throw CLIError.usage("--from and --to are required (or --scenario FILE)") }
            guard seed != nil else { throw CLIError.usage("--seed is required (or --scenario FILE)") }
            scenario = SimulationScenario(name: "cli", map: mapOption ?? "office", from: from, to: to, seed: 0)
        }
        if let m = mapOption { scenario.map = m }
        if let f = from { scenario.from = f }
        if let t = to { scenario.to = t }
        if let s = seed {
            guard let v = UInt64(s) else { throw CLIError.usage("--seed must be a non-negative integer, got '\(s)'") }
            scenario.seed = v
        }
        if let c = try arguments.option("carry") {
            guard let v = CarryMode(rawValue: c) else { throw CLIError.usage("--carry must be handheld or lanyard") }
            scenario.carry = v
        }
        if let o = try arguments.option("orientation") {
            guard let v = PhoneOrientation(rawValue: o) else { throw CLIError.usage("--orientation must be portrait or landscape") }
            scenario.orientation = v
        }
        if let r = try arguments.doubleOption("rate") { scenario.rateHz = r }
        if let r = try arguments.doubleOption("detector-rate") { scenario.detectorRateHz = r }
        if arguments.flag("images") { scenario.images = true }
        if let r = try arguments.doubleOption("image-rate") { scenario.imageRateHz = r }
        let floorOnly = arguments.flag("floor-only-start"), known = arguments.flag("known-start")
        if floorOnly && known { throw CLIError.usage("--floor-only-start and --known-start exclude each other") }
        if known { scenario.startKnown = true }
        if floorOnly { scenario.startKnown = false }
        if let t = try arguments.doubleOption("tracking-loss") { scenario.trackingLossAt = t }
        if let d = try arguments.doubleOption("tracking-loss-duration") { scenario.trackingLossDurationSeconds = d }
        if let t = try arguments.doubleOption("vio-reset") { scenario.vioResetAt = t }
        if arguments.flag("wrong-turn") { scenario.wrongTurn = true }
        if let n = try arguments.doubleOption("north-offset") { scenario.mapNorthOffsetDeg = n }
        if let m = try arguments.doubleOption("tour-minutes") { scenario.tourMinutes = m }
        let overwrite = arguments.flag("overwrite")
        var output = try arguments.option("output")
        var rest = try arguments.positionals()
        if let i = rest.firstIndex(of: "-o") {
            guard i + 1 < rest.count else { throw CLIError.usage("-o needs a value") }
            output = rest[i + 1]
            rest.removeSubrange(i...(i + 1))
        }
        guard rest.isEmpty else { throw CLIError.usage("unexpected arguments: \(rest.joined(separator: " "))") }
        guard let out = output else { throw CLIError.usage("missing -o BUNDLE") }
        do { try scenario.validate() } catch { throw CLIError.usage("\(error)") }

        let building = try loadMap(scenario.map)
        scenario.from = try resolvePlace(scenario.from, flag: "--from", in: building, mapSpec: scenario.map)
        scenario.to = try resolvePlace(scenario.to, flag: "--to", in: building, mapSpec: scenario.map)
        let walk: SimulatedWalk
        do { walk = try WalkSimulator.simulate(building: building, scenario: scenario, parameters: simulation) } catch {
            throw CLIError.failure("\(error)")
        }
        do { try walk.write(to: URL(fileURLWithPath: out), overwrite: overwrite) } catch {
            throw CLIError.failure("\(out): \(error)")
        }
        let duration = walk.truth.last?.t ?? 0
        note(String(format: "simulate: %d frames (%.1f s), %d observations, %d images -> %@", walk.frames.count, duration,
                        walk.observations.count, walk.imageFrameIndices.count, out))
        return 0
    }
}
