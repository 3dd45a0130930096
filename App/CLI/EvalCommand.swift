import Evaluation
import Foundation
import Maps
import SessionFormat
import Simulation
import WayfinderCore

/// `wayfinder eval`: replays walks and scores them against truth, with a regression gate.
enum EvalCommand: Subcommand {
    static let name = "eval"
    static let summary = "score replays against truth (localization and navigation), with a regression gate"
    static let usage = """
    Usage: wayfinder eval BUNDLE... --map MAP [--detector recorded|cascade|unet|auto] [--models DIR] [--json] [--explain]
                          [--baseline FILE] [--write-baseline FILE] [--seed N]
           wayfinder eval --scenarios DIR [--skeri DIR] [--survey-placards] [--sim-detector NAME] [--sim-params FILE] [--json] [--explain]
                          [--baseline FILE] [--write-baseline FILE] [--seed N]

    Replays each bundle (which must have truth.jsonl) through the real pipeline and prints, per walk:
    time and distance to first convergence, median/90th/95th percentile position error after convergence,
    heading error, share of time localized, confidently-wrong episodes (localized and > 3 m off), true turns,
    cued turns, missing and wrong instructions, median cue distance before the control point and the true
    distance at arrival; then the aggregate. --json prints JSON instead. --baseline fails (exit 1) when an
    aggregate figure is worse than the baseline by more than its tolerance; --write-baseline writes one.
    --scenarios simulates and scores every scenario definition (*.json) in DIR in memory.
    --seed N sets the particle filter's seed for every replay (default 1; the simulated walks do not change).
    --survey-placards adds a room-number placard beside every room-like place of the map before simulating and
    replaying (a study of identifying signs: PlacardSurvey, docs/benchmarks.md "Placards").
    --sim-detector (with --scenarios) simulates the walks behind another detector's noise (below;
    docs/benchmarks.md "Behind the real detectors' errors").
    --explain prints to standard error, for every cue scored wrong, every turn scored missing and every
    instruction while not localized that is unsafe from the true pose, the true and estimated positions, the
    true turns and the phrases around it.
    True turns are found from truth.jsonl alone (a change of walking direction over a few meters, matched to
    the graph node where the route turns; see docs/evaluation.md); a truth floor that the map lacks is an error.
    \(MapSpec.usageLine).
    \(EvidenceSwitches.usage)
    \(SimDetectorOption.usage)
    Exit codes: 0 ok, 1 bad input (map, bundle, scenarios) or a regression against --baseline, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let json = arguments.flag("json")
        let explain = arguments.flag("explain")
        let baselinePath = try arguments.option("baseline")
        let writeBaselinePath = try arguments.option("write-baseline")
        let scenariosDir = try arguments.option("scenarios")
        let skeriDir = try arguments.option("skeri")
        let mapPath = try arguments.option("map")
        let surveyPlacards = arguments.flag("survey-placards")
        let adjustMap: (Building) -> Building = { surveyPlacards ? PlacardSurvey.addingPlacards(to: $0) : $0 }
        let (simulation, simDetectorGiven) = try SimDetectorOption.parse(&arguments)
        if simDetectorGiven && scenariosDir == nil { throw CLIError.usage("--sim-detector, --sim-params and --sim-range-bias only apply to --scenarios") }
        var pipeline = PipelineOptions()
        try EvidenceSwitches.apply(&arguments, to: &pipeline)
        if let seed = try arguments.seedOption() { pipeline.seed = seed }
        let bundles = try arguments.positionals()

        var scores: [WalkScore] = []
        func explainWalk(_ score: WalkScore, _ result: ReplayResult, _ building: Building, _ truth: [TruthRecord]) {
            guard explain else { return }
            for line in WalkExplanation.lines(score: score, result: result, truth: truth, building: building) {
                FileHandle.standardError.write(Data((line + "\n").utf8))
            }
        }
        if let scenariosDir {
            var isDirectory: ObjCBool = false
            guard FileManager.default.fileExists(atPath: scenariosDir, isDirectory: &isDirectory), isDirectory.boolValue else {
                throw CLIError.failure("\(scenariosDir): no such scenario folder")
            }
            do {
                scores = try ScenarioRunner.scoreAll(directory: URL(fileURLWithPath: scenariosDir),
                                                     skeriDirectory: skeriDir.map { URL(fileURLWithPath: $0) },
                                                     options: pipeline, adjustMap: adjustMap,
                                                     parameters: simulation, progress: progress,
                                                     inspect: { explainWalk($0, $1, $2, $3.truth) })
            } catch {
                throw CLIError.failure("\(scenariosDir): \(error)")
            }
        } else {
            guard !bundles.isEmpty else { throw CLIError.usage("give BUNDLE directories or --scenarios DIR") }
            guard let mapPath else { throw CLIError.usage("missing --map") }
            let building = adjustMap(try loadMap(mapPath))
            for path in bundles {
                let bundle = try loadBundle(path)
                progress("eval: \(path)")
                do {
                    let (score, result) = try WalkEvaluator.evaluate(name: bundle.url.lastPathComponent, bundle: bundle,
                                                                     building: building, options: pipeline)
                    for w in (bundle.warnings.map { "\($0)" } + result.warnings).prefix(5) { note("warning: \(path): \(w)") }
                    explainWalk(score, result, building, bundle.truth)
                    scores.append(score)
                } catch {
                    throw CLIError.failure("\(path): \(error)")
                }
            }
        }
        let aggregate = AggregateScore(scores)
        if json {
            struct Output: Encodable { let walks: [WalkScore]; let aggregate: AggregateScore }
            let e = JSONEncoder()
            e.outputFormatting = [.prettyPrinted, .sortedKeys]
            print(String(decoding: try e.encode(Output(walks: scores, aggregate: aggregate)), as: UTF8.self))
        } else {
            print(ScoreTable.render(scores, aggregate: aggregate), terminator: "")
        }
        if let writeBaselinePath {
            do { try RegressionBaseline(aggregate: aggregate).write(to: URL(fileURLWithPath: writeBaselinePath)) } catch {
                throw CLIError.failure("cannot write baseline \(writeBaselinePath): \(error.localizedDescription)")
            }
            note("eval: baseline written to \(writeBaselinePath)")
        }
        if let baselinePath {
            let baseline: RegressionBaseline
            do { baseline = try RegressionBaseline.load(URL(fileURLWithPath: baselinePath)) } catch {
                throw CLIError.failure("\(error)")
            }
            let regressions = baseline.regressions(of: aggregate)
            if !regressions.isEmpty {
                for r in regressions { FileHandle.standardError.write(Data("regression: \(r)\n".utf8)) }
                return 1
            }
            note("eval: no regression against \(baselinePath)")
        }
        return 0
    }
}
