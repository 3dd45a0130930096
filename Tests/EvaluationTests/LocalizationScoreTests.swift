import XCTest
import SessionFormat
import WayfinderCore
@testable import Evaluation

/// Metric tests on hand-made truth/trace pairs: a straight walk along +x at 1 m/s, 10 Hz.
final class LocalizationScoreTests: XCTestCase {
    func straightTruth(seconds: Double = 30) -> [TruthRecord] {
        stride(from: 0.0, through: seconds, by: 0.1).map { TruthRecord(t: $0, x: $0, y: 0, floorId: "1", headingRad: 0) }
    }

    func trace(_ truth: [TruthRecord], localizedFrom: Double, offset: (Double) -> Double) -> [TraceRecord] {
        truth.map { r in
            TraceRecord(t: r.t, x: r.x + offset(r.t), y: r.y, floorId: "1", headingRad: 0, confidence: 0.9,
                        localized: r.t >= localizedFrom, hypotheses: 1, sightings: 0, announcements: [], haptics: [])
        }
    }

    func testConvergenceTimeDistanceAndPercentiles() {
        let truth = straightTruth()
        // Error 0.2 m before t=20, 0.6 m after: after convergence at t=10, 100 frames at 0.2 and 101 at 0.6.
        let score = LocalizationScore(trace: trace(truth, localizedFrom: 10) { $0 < 20 ? 0.2 : 0.6 }, truth: TruthTrack(truth))
        XCTAssertEqual(score.timeToConvergenceSeconds!, 10, accuracy: 1e-9)
        XCTAssertEqual(score.distanceToConvergenceMeters!, 10, accuracy: 1e-6)
        XCTAssertEqual(score.medianErrorMeters!, 0.6, accuracy: 1e-6)
        XCTAssertEqual(score.p95ErrorMeters!, 0.6, accuracy: 1e-6)
        XCTAssertEqual(score.fractionLocalized, 201.0 / 301.0, accuracy: 1e-9)
        XCTAssertEqual(score.wrongConvergenceEpisodes, 0)
        XCTAssertEqual(score.walkedMeters, 30, accuracy: 1e-6)
    }

    func testSteadyLockShareAndFloorChangeRelocalization() {
        // 30 m along +x; the walker changes to floor 2 at t = 15 (an elevator ride without walking is not
        // needed for the metric). The trace is localized from t = 5, drops at 15-18 and is back on floor 2 at 18.
        let truth = stride(from: 0.0, through: 30, by: 0.1).map {
            TruthRecord(t: $0, x: $0, y: 0, floorId: $0 < 15 ? "1" : "2", headingRad: 0)
        }
        let trace = truth.map { r in
            TraceRecord(t: r.t, x: r.x, y: r.y, floorId: r.t < 15.5 ? "1" : "2", headingRad: 0, confidence: 0.9,
                        localized: r.t >= 5 && !(r.t >= 15 && r.t < 18), hypotheses: 1, sightings: 0, announcements: [],
                        haptics: [])
        }
        let score = LocalizationScore(trace: trace, truth: TruthTrack(truth))
        // 15.0-15.4: localized? no (dropped 15-18); the estimate's floor lags the truth by 0.5 s: riding, not wrong.
        XCTAssertEqual(score.wrongConvergenceEpisodes, 0)
        // After convergence (t >= 5: 251 frames), 30 frames (15.0 ... 17.9) are not localized.
        XCTAssertEqual(score.framesAfterConvergence, 251)
        XCTAssertEqual(score.localizedShareAfterConvergence!, 221.0 / 251.0, accuracy: 1e-9)
        XCTAssertEqual(score.floorChangeRelocalizationMeters!, 3.0, accuracy: 1e-6)
        XCTAssertFalse(score.floorChangeNeverRelocalized)
        // Without a floor change there is no figure.
        XCTAssertNil(LocalizationScore(trace: self.trace(straightTruth(), localizedFrom: 5) { _ in 0 },
                                       truth: TruthTrack(straightTruth())).floorChangeRelocalizationMeters)
    }

    func testAnEstimateLeftOnTheOldFloorIsRidingOnlyForAFewSeconds() {
        // Truth changes to floor 2 at t = 10; the estimate stays localized on floor 1 until t = 20.
        let truth = stride(from: 0.0, through: 30, by: 0.1).map {
            TruthRecord(t: $0, x: $0, y: 0, floorId: $0 < 10 ? "1" : "2", headingRad: 0)
        }
        let trace = truth.map { r in
            TraceRecord(t: r.t, x: r.x, y: r.y, floorId: r.t < 20 ? "1" : "2", headingRad: 0, confidence: 0.9,
                        localized: true, hypotheses: 1, sightings: 0, announcements: [], haptics: [])
        }
        let score = LocalizationScore(trace: trace, truth: TruthTrack(truth))
        // 10-15 s riding (grace), 15-20 s confidently wrong: one episode.
        XCTAssertEqual(score.wrongConvergenceEpisodes, 1)
        XCTAssertEqual(score.wrongConvergenceSeconds, 5, accuracy: 0.15)
    }

    func testNeverConvergedHasNoErrorFigures() {
        let truth = straightTruth()
        let score = LocalizationScore(trace: trace(truth, localizedFrom: 1e9) { _ in 0 }, truth: TruthTrack(truth))
        XCTAssertNil(score.timeToConvergenceSeconds)
        XCTAssertNil(score.medianErrorMeters)
        XCTAssertEqual(score.fractionLocalized, 0)
    }

    func testWrongConvergenceEpisodesAreCountedSeparately() {
        let truth = straightTruth()
        // Two confidently-wrong spells: 5-8 s and 15-17 s (5 m off), localized throughout.
        let score = LocalizationScore(trace: trace(truth, localizedFrom: 0) { t in
            (t >= 5 && t < 8) || (t >= 15 && t < 17) ? 5 : 0.1
        }, truth: TruthTrack(truth))
        XCTAssertEqual(score.wrongConvergenceEpisodes, 2)
        XCTAssertEqual(score.wrongConvergenceSeconds, 5, accuracy: 0.11)
        XCTAssertEqual(score.maxWrongConvergenceDistanceMeters, 2.9, accuracy: 0.11)
    }

    func testPercentileMatchesNumpyDefault() {
        XCTAssertEqual(percentile([1, 2, 3, 4], 50)!, 2.5, accuracy: 1e-12)
        XCTAssertEqual(percentile([1, 2, 3, 4, 5, 6, 7, 8, 9, 10], 90)!, 9.1, accuracy: 1e-12)
        XCTAssertNil(percentile([], 50))
    }

    func testTruthInterpolation() {
        let track = TruthTrack(straightTruth())
        XCTAssertEqual(track.state(at: 3.05).x, 3.05, accuracy: 1e-9)
        XCTAssertEqual(track.distanceWalked(at: 12.34), 12.34, accuracy: 1e-9)
    }

    func testRegressionGateFlagsWorseFigures() {
        let truth = straightTruth()
        let good = WalkScore(name: "a", localization: LocalizationScore(trace: trace(truth, localizedFrom: 5) { _ in 0.3 }, truth: TruthTrack(truth)),
                             navigation: NavigationScore(announcements: [], truth: TruthTrack(truth),
                                                         building: .init(id: "b", name: "b", floors: [], graph: .init(nodes: [], edges: [])),
                                                         destination: nil, convergenceT: 5), frames: 301, durationSeconds: 30)
        var bad = good
        bad.localization = LocalizationScore(trace: trace(truth, localizedFrom: 5) { _ in 0.9 }, truth: TruthTrack(truth))
        let baseline = RegressionBaseline(aggregate: AggregateScore([good]))
        XCTAssertTrue(baseline.regressions(of: AggregateScore([good])).isEmpty)
        let found = baseline.regressions(of: AggregateScore([bad]))
        XCTAssertTrue(found.contains { $0.hasPrefix("median error") }, "\(found)")
    }

    /// A drop of exactly the tolerance passes whatever the doubles round to; one walk more fails.
    func testRegressionGateTakesADropOfExactlyTheToleranceAsPassing() {
        var base = AggregateScore([])
        base.walks = 30
        base.convergedWithin20mShare = 13.0 / 30.0
        let baseline = RegressionBaseline(aggregate: base, convergenceShareTolerance: 0.1)
        XCTAssertLessThan(10.0 / 30.0, 13.0 / 30.0 - 0.1, "the doubles this test is about")
        var now = base
        now.convergedWithin20mShare = 10.0 / 30.0
        XCTAssertTrue(baseline.regressions(of: now).isEmpty, "\(baseline.regressions(of: now))")
        now.convergedWithin20mShare = 9.0 / 30.0
        XCTAssertTrue(baseline.regressions(of: now).contains { $0.hasPrefix("converged within 20 m") })
    }
}
