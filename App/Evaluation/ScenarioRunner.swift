import Foundation
import Maps
import SessionFormat
import Simulation
import WayfinderCore

/// Simulates the committed scenario definitions (Tests/Scenarios/*.json) in memory and scores each through
/// the real pipeline: what CI's scenario suite runs (scripts/run-scenarios.sh).
public enum ScenarioRunner {
    /// Loads every `*.json` scenario in `directory`, sorted by file name. Errors name the file.
    public static func loadScenarios(directory: URL) throws -> [SimulationScenario] {
        let files = try FileManager.default.contentsOfDirectory(at: directory, includingPropertiesForKeys: nil)
            .filter { $0.pathExtension == "json" }.sorted { $0.lastPathComponent < $1.lastPathComponent }
        return try files.map { try SimulationScenario.load(contentsOf: $0) }
    }

    /// The bundle a simulated walk would write, without touching the disk.
    public static func bundle(of walk: SimulatedWalk, name: String) -> SessionBundle {
        var b = SessionBundle(url: URL(fileURLWithPath: "/scenario/\(name)"), info: walk.info, frames: walk.frames,
                              observations: walk.observations, truth: walk.truth, expected: walk.expected, warnings: [])
        b.planes = walk.planes
        return b
    }

    /// Simulates and scores one scenario. `adjustMap` changes the building before the walk (a study's extra
    /// survey, e.g. `PlacardSurvey.addingPlacards`); the walk and the replay both see the adjusted map.
    /// `parameters` are the simulator's noise models (default: docs/simulator.md; a stress study swaps in
    /// another detector, e.g. `DetectorParameters.realPhotoUNet`).
    public static func score(_ scenario: SimulationScenario, sharedData: URL?, options: PipelineOptions,
                             adjustMap: (Building) -> Building = { $0 },
                             parameters: SimulationParameters = .standard) throws -> (WalkScore, ReplayResult, Building, SessionBundle) {
        let building = adjustMap(try ScenarioMaps.load(scenario.map, sharedData: sharedData))
        let walk = try WalkSimulator.simulate(building: building, scenario: scenario, parameters: parameters)
        let bundle = bundle(of: walk, name: scenario.name)
        let (score, result) = try WalkEvaluator.evaluate(name: scenario.name, bundle: bundle, building: building, options: options)
        return (score, result, building, bundle)
    }

    /// Simulates and scores every scenario in `directory`. `skeriDirectory` is the folder that holds
    /// `skeri_inavigate` (default ../shared/data); `adjustMap` and `parameters` as for `score`. Progress lines go to
    /// `progress`; `inspect`, when given, sees each walk's score, replay, map and bundle as it is scored.
    public static func scoreAll(directory: URL, skeriDirectory: URL?, options: PipelineOptions,
                                adjustMap: (Building) -> Building = { $0 },
                                parameters: SimulationParameters = .standard,
                                progress: (String) -> Void,
                                inspect: ((WalkScore, ReplayResult, Building, SessionBundle) -> Void)? = nil) throws -> [WalkScore] {
        let scenarios = try loadScenarios(directory: directory)
        var scores: [WalkScore] = []
        for s in scenarios {
            let start = Date()
            let (score, result, building, bundle) = try Self.score(s, sharedData: skeriDirectory, options: options,
                                                                   adjustMap: adjustMap, parameters: parameters)
            inspect?(score, result, building, bundle)
            progress(String(format: "scenario %@: %.1f s walk scored in %.1f s", s.name, score.durationSeconds, Date().timeIntervalSince(start)))
            scores.append(score)
        }
        return scores
    }
}
