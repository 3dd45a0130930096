import XCTest
@testable import Simulation

/// `SimulationParametersOverlay`: partial parameter files laid over the defaults, and the committed stress
/// profiles (Tests/StressProfiles) that `eval --sim-params` runs.
final class SimulationParametersOverlayTests: XCTestCase {
    private func apply(_ json: String, to base: SimulationParameters = .standard) throws -> SimulationParameters {
        try SimulationParametersOverlay.apply(Data(json.utf8), to: base)
    }

    func testTheGivenKeysChangeAndEveryOtherParameterKeepsItsValue() throws {
        let p = try apply(#"{"vio": {"scaleErrorRange": [0.03, 0.1], "yawRandomWalkDegPerSqrtMinute": 1.5}, "detector": {"bearingSigmaDeg": 4}}"#)
        var expected = SimulationParameters.standard
        expected.vio.scaleErrorRange = 0.03...0.1
        expected.vio.yawRandomWalkDegPerSqrtMinute = 1.5
        expected.detector.bearingSigmaDeg = 4
        XCTAssertEqual(p, expected)
    }

    func testTheOverlayIsLaidOverTheBaseItIsGivenNotOverTheDefaults() throws {
        var base = SimulationParameters.standard
        base.detector = .realPhotoCascade
        let p = try apply(#"{"detector": {"falsePositivesPerFrame": 0.1}}"#, to: base)
        XCTAssertEqual(p.detector.rangeBias, -0.25)
        XCTAssertEqual(p.detector.falsePositivesPerFrame, 0.1)
    }

    func testAnEmptyObjectGivesTheBaseUnchanged() throws {
        XCTAssertEqual(try apply("{}"), .standard)
    }

    func testAMisspeltKeyIsAnErrorNamingItsPath() {
        XCTAssertThrowsError(try apply(#"{"vio": {"scaleErorRange": [0, 1]}}"#)) { error in
            XCTAssertEqual(error as? SimulationParametersOverlay.OverlayError, .unknownKey("vio.scaleErorRange"))
        }
        XCTAssertThrowsError(try apply(#"{"lidar": {}}"#)) { error in
            XCTAssertEqual(error as? SimulationParametersOverlay.OverlayError, .unknownKey("lidar"))
        }
    }

    func testValuesOfTheWrongShapeOrOutsideTheModelsLimitsAreErrors() {
        // A reversed range, a string for a number, an object where a number is expected, a non-object document.
        for json in [#"{"vio": {"scaleErrorRange": [0.1, 0.03]}}"#, #"{"detector": {"bearingSigmaDeg": "four"}}"#,
                     #"{"detector": {"bearingSigmaDeg": {"deg": 4}}}"#, "[1, 2]", "not json"] {
            XCTAssertThrowsError(try apply(json), json)
        }
        // Decodes, but the models cannot run with it: validate() names it.
        XCTAssertThrowsError(try apply(#"{"detector": {"falsePositivesPerFrame": 2}}"#)) { error in
            guard case .invalid(let message)? = error as? SimulationParametersOverlay.OverlayError else {
                return XCTFail("expected .invalid, got \(error)")
            }
            XCTAssertTrue(message.contains("falsePositivesPerFrame"), message)
        }
        XCTAssertThrowsError(try apply(#"{"detector": {"scoresTellFalsePositives": false, "constantScore": 1.5}}"#)) { error in
            guard case .invalid(let message)? = error as? SimulationParametersOverlay.OverlayError else {
                return XCTFail("expected .invalid, got \(error)")
            }
            XCTAssertTrue(message.contains("constantScore"), message)
        }
    }

    func testEveryCommittedStressProfileAppliesAndChangesSomething() throws {
        let dir = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent()
            .appendingPathComponent("StressProfiles")
        let files = try FileManager.default.contentsOfDirectory(at: dir, includingPropertiesForKeys: nil)
            .filter { $0.pathExtension == "json" }
        XCTAssertGreaterThanOrEqual(files.count, 6)
        for file in files {
            let p = try SimulationParametersOverlay.apply(try Data(contentsOf: file), to: .standard)
            XCTAssertNotEqual(p, .standard, file.lastPathComponent)
        }
    }
}
