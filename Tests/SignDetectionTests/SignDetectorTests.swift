import Foundation
import XCTest
import Maps
@testable import SignDetection

/// Tests of the SignDetection wrapper against the real C++ detector: the reference cascade (read in place
/// from ../shared) and the tiny committed red-pixel ONNX model (Tests/SignDetector/data).
final class SignDetectorTests: XCTestCase {
    private static let repoRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent()
        .deletingLastPathComponent().deletingLastPathComponent()
    private static let tinyUnet = repoRoot.appendingPathComponent("Tests/SignDetector/data/tiny_red_unet.onnx").path
    private static let referenceCascade = repoRoot.deletingLastPathComponent()
        .appendingPathComponent("shared/data/skeri_inavigate/models/exit_sign_cascade.xml").path

    /// 640 x 480 RGB wall (gray 120) with a red plate covering raw columns 300..339 and rows 200..259.
    private func redPlateFrame() -> ImageBuffer {
        let width = 640, height = 480
        var pixels = [UInt8](repeating: 120, count: width * height * 3)
        for v in 200..<260 {
            for u in 300..<340 {
                let i = (v * width + u) * 3
                pixels[i] = 220; pixels[i + 1] = 25; pixels[i + 2] = 25
            }
        }
        return ImageBuffer(width: width, height: height, bytesPerRow: width * 3, pixelFormat: .rgb8, data: pixels)
    }

    private func unetDetector() throws -> SignDetector {
        try SignDetector(configuration: DetectorConfiguration(kind: .unet, unetPath: Self.tinyUnet))
    }

    func testMissingModelThrowsModelLoadNamingTheFile() {
        let config = DetectorConfiguration(kind: .cascade, cascadePath: "/nonexistent/exit.xml")
        XCTAssertThrowsError(try SignDetector(configuration: config)) { error in
            guard case SignDetectorError.modelLoad(let message) = error else {
                return XCTFail("expected modelLoad, got \(error)")
            }
            XCTAssertTrue(message.contains("/nonexistent/exit.xml"), message)
        }
        XCTAssertThrowsError(try SignDetector(configuration: DetectorConfiguration(kind: .unet)))
    }

    func testReferenceCascadeLoadsAndRunsOnAPlainFrame() throws {
        let detector = try SignDetector(configuration: DetectorConfiguration(kind: .cascade, cascadePath: Self.referenceCascade))
        XCTAssertEqual(detector.kinds, ["exit"])
        let frame = ImageBuffer.gray(width: 640, height: 480, pixels: [UInt8](repeating: 128, count: 640 * 480))
        let found = try detector.detect(image: frame, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: -Double.pi / 2)
        XCTAssertTrue(found.isEmpty)
    }

    func testCascadePlacementPriorAndCrowdedGateOptionsReachTheDetector() throws {
        var config = DetectorConfiguration(kind: .cascade, cascadePath: Self.referenceCascade)
        XCTAssertEqual(config.cascadeSignAboveCameraMeters, 0.3...2.0)
        XCTAssertNoThrow(try SignDetector(configuration: config))
        config.cascadeSignAboveCameraMeters = nil  // every row
        XCTAssertNoThrow(try SignDetector(configuration: config))
        func expectInvalid(_ fragment: String, _ c: DetectorConfiguration, line: UInt = #line) {
            XCTAssertThrowsError(try SignDetector(configuration: c), line: line) { error in
                guard case SignDetectorError.invalidArgument(let message) = error else {
                    return XCTFail("expected invalidArgument, got \(error)", line: line)
                }
                XCTAssertTrue(message.contains(fragment), message, line: line)
            }
        }
        config.cascadeSignAboveCameraMeters = 1.0...1.0  // an empty band: the C side rejects min == max
        expectInvalid("cascade_sign_above_camera_min_m", config)
        config.cascadeSignAboveCameraMeters = -1.0...0.0  // signs at or below camera height: a valid band
        XCTAssertNoThrow(try SignDetector(configuration: config))
        config.cascadeSignAboveCameraMeters = 0.0...0.0  // sent as 1 nm ... 1 nm: empty, rejected (not the defaults)
        expectInvalid("cascade_sign_above_camera_min_m", config)
        config.cascadeSignAboveCameraMeters = 0.3...2.0
        config.cascadeGateCrowdedContrastFactor = 0.5
        expectInvalid("cascade_gate_crowded_contrast_factor", config)
        config.cascadeGateCrowdedContrastFactor = 1  // off
        XCTAssertNoThrow(try SignDetector(configuration: config))
        config.cascadeGateMinMarginPixels = -1
        expectInvalid("cascade_gate_min_margin_px", config)
        config.cascadeGateMinMarginPixels = 24  // the earlier, wider margins
        XCTAssertNoThrow(try SignDetector(configuration: config))
        config.cascadeGateComponentWindowFraction = 1.5
        expectInvalid("cascade_gate_component_window_fraction", config)
        config.cascadeGateComponentWindowFraction = nil  // off: sent as -1
        XCTAssertNoThrow(try SignDetector(configuration: config))
        config.cascadeGateComponentWindowFraction = 0.5
        XCTAssertNoThrow(try SignDetector(configuration: config))
    }

    func testTwoCascadeKindsAreReported() throws {
        var config = DetectorConfiguration(kind: .cascade)
        config.cascades = [CascadeModel(kind: "exit", path: Self.referenceCascade),
                           CascadeModel(kind: "restroom", path: Self.referenceCascade)]
        XCTAssertEqual(try SignDetector(configuration: config).kinds, ["exit", "restroom"])
    }

    func testUnetFindsThePlateInAPortraitFrameAndMeasuresIt() throws {
        let detector = try unetDetector()
        XCTAssertEqual(detector.kinds, ["exit"])  // from classes.json next to the model
        let found = try detector.detect(image: redPlateFrame(), fx: 534, fy: 530, cx: 319.5, cy: 239.5,
                                        pitchRad: 0.05, rollRad: -Double.pi / 2)
        XCTAssertEqual(found.count, 1)
        let sign = try XCTUnwrap(found.first)
        XCTAssertEqual(sign.kind, "exit")
        XCTAssertGreaterThan(sign.score, 0.9)
        // Portrait: the raw u extent (40 px) is the unrolled height; fx and fy swap; cx' = H - 1 - cy.
        XCTAssertEqual(sign.medianHeightPx, 40, accuracy: 1.5)
        XCTAssertEqual(sign.unrolledFx, 530)
        XCTAssertEqual(sign.unrolledFy, 534)
        XCTAssertEqual(sign.unrolledCx, 479 - 239.5)
        XCTAssertEqual(sign.unrolledCy, 319.5)
        XCTAssertEqual(sign.unrolledWidth, 480)
        XCTAssertEqual(sign.unrolledHeight, 640)
        // The bottom edge in the unrolled image is the raw plate's right edge (u = 339.5).
        XCTAssertEqual(sign.medianBottomRowPx, 339.5, accuracy: 1.5)
        // The centre maps back to the raw plate's centre (319.5, 229.5).
        let centre = sign.rawPoint(u: sign.centerColumnPx, v: sign.medianBottomRowPx - sign.medianHeightPx / 2)
        XCTAssertEqual(centre.u, 319.5, accuracy: 1.5)
        XCTAssertEqual(centre.v, 229.5, accuracy: 1.5)
        XCTAssertEqual(sign.boxInUnrolled.width, 60, accuracy: 2)
    }

    func testUnetCoarseElevationCutIsPassedToTheDetector() throws {
        // Camera pitched 0.3 rad down: the plate's centre is at elevation ~-0.3 rad, below the default cut
        // (-0.10 rad) and below the far-band pass, so only a whole-frame coarse pass (nil) finds it.
        var config = DetectorConfiguration(kind: .unet, unetPath: Self.tinyUnet)
        let cut = try SignDetector(configuration: config)
        XCTAssertEqual(try cut.detect(image: redPlateFrame(), fx: 534, fy: 530, cx: 319.5, cy: 239.5,
                                      pitchRad: -0.3, rollRad: -Double.pi / 2).count, 0)
        config.unetCoarseMinElevationRad = nil
        let whole = try SignDetector(configuration: config)
        XCTAssertEqual(try whole.detect(image: redPlateFrame(), fx: 534, fy: 530, cx: 319.5, cy: 239.5,
                                        pitchRad: -0.3, rollRad: -Double.pi / 2).count, 1)
    }

    func testBadFramesThrowBadFrame() throws {
        let detector = try unetDetector()
        let frame = redPlateFrame()
        func expectBadFrame(_ fragment: String, _ body: () throws -> Void, line: UInt = #line) {
            XCTAssertThrowsError(try body(), line: line) { error in
                guard case SignDetectorError.badFrame(let message) = error else {
                    return XCTFail("expected badFrame, got \(error)", line: line)
                }
                XCTAssertTrue(message.contains(fragment), message, line: line)
            }
        }
        expectBadFrame("pitch") {
            _ = try detector.detect(image: frame, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: .nan, rollRad: 0)
        }
        expectBadFrame("roll") {
            _ = try detector.detect(image: frame, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: .infinity)
        }
        expectBadFrame("another resolution") {
            _ = try detector.detect(image: frame, fx: 1602, fy: 1602, cx: 959.5, cy: 719.5, pitchRad: 0, rollRad: 0)
        }
        var short = frame
        short.data.removeLast(10)
        expectBadFrame("needs") {
            _ = try detector.detect(image: short, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: 0)
        }
        expectBadFrame("empty") {
            _ = try detector.detect(image: ImageBuffer.gray(width: 0, height: 0, pixels: []), fx: 1, fy: 1, cx: 0, cy: 0,
                                    pitchRad: 0, rollRad: 0)
        }
    }

    func testDarkFrameIsSkippedWithAWarning() throws {
        let detector = try unetDetector()
        let dark = ImageBuffer.gray(width: 640, height: 480, pixels: [UInt8](repeating: 0, count: 640 * 480))
        let outcome = try detector.detectFrame(image: dark, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: 0)
        XCTAssertTrue(outcome.detections.isEmpty)
        XCTAssertTrue(outcome.warning?.contains("mean luma") ?? false, outcome.warning ?? "nil")
    }

    func testNv12LumaAndChromaPlanes() throws {
        let detector = try unetDetector()
        let width = 640, height = 480
        var luma = [UInt8](repeating: 120, count: width * height)
        var chroma = [UInt8](repeating: 128, count: width * height / 2)
        // Full-range red plate shaped like an Exit sign (2:1, the detector rejects other shapes): Y 90, Cb 100,
        // Cr 220 over raw columns 260..379, rows 200..259.
        for v in 200..<260 {
            for u in 260..<380 { luma[v * width + u] = 90 }
        }
        for v in 100..<130 {
            for u in 130..<190 { chroma[v * width + 2 * u] = 100; chroma[v * width + 2 * u + 1] = 220 }
        }
        let image = ImageBuffer(width: width, height: height, bytesPerRow: width, pixelFormat: .nv12, data: luma,
                                chromaBytesPerRow: width, chromaData: chroma)
        let found = try detector.detect(image: image, fx: 534, fy: 534, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: 0)
        XCTAssertEqual(found.count, 1)
        XCTAssertEqual(found.first?.medianHeightPx ?? 0, 60, accuracy: 1.5)
    }

    func testImageLoadReadsAFileAndNamesAMissingOne() throws {
        // A 4 x 3 binary PGM written by hand.
        let path = FileManager.default.temporaryDirectory.appendingPathComponent("signdetection-\(getpid()).pgm").path
        var bytes = Array("P5\n4 3\n255\n".utf8)
        bytes += (0..<12).map { UInt8($0 * 20) }
        XCTAssertTrue(FileManager.default.createFile(atPath: path, contents: Data(bytes)))
        defer { try? FileManager.default.removeItem(atPath: path) }
        let gray = try ImageBuffer.load(path: path, pixelFormat: .gray8)
        XCTAssertEqual(gray.width, 4)
        XCTAssertEqual(gray.height, 3)
        XCTAssertEqual(gray.data, (0..<12).map { UInt8($0 * 20) })
        let rgb = try ImageBuffer.load(path: path)
        XCTAssertEqual(rgb.bytesPerRow, 12)
        XCTAssertEqual(Array(rgb.data[3..<6]), [20, 20, 20])
        XCTAssertThrowsError(try ImageBuffer.load(path: "/nonexistent/frame.png")) { error in
            XCTAssertEqual(error as? SignDetectorError,
                           .imageRead("cannot read or decode image file /nonexistent/frame.png"))
        }
    }

    func testBundledConfigurationUsesTheModelsDirectory() {
        let dir = Self.repoRoot.appendingPathComponent("Tests/SignDetector/data").path
        let cascade = DetectorConfiguration.bundled(kind: .cascade, modelsDirectory: dir)
        XCTAssertEqual(cascade.kind, .cascade)
        XCTAssertEqual(cascade.cascadePath, dir + "/exit_sign_cascade.xml")
        XCTAssertEqual(cascade.cascades.first?.kind, "exit")
        let unet = DetectorConfiguration.bundled(kind: .unet, modelsDirectory: dir)
        XCTAssertEqual(unet.unetPath, dir + "/sign_unet.onnx")
        XCTAssertEqual(unet.classNames, ["background", "exit"])
    }

    func testErrorsDescribeThemselves() {
        XCTAssertEqual(SignDetectorError.badFrame("x").description, "bad frame: x")
        XCTAssertEqual(SignDetectorError.modelLoad("m").message, "m")
        XCTAssertFalse(SignDetector.libraryVersion.isEmpty)
    }
}

/// `SignDetector.sense`: one C call per frame from pixels to ranged signs, with sizes from the catalogue.
final class SignSenseTests: XCTestCase {
    private static let repoRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent()
        .deletingLastPathComponent().deletingLastPathComponent()
    private static let tinyUnet = repoRoot.appendingPathComponent("Tests/SignDetector/data/tiny_red_unet.onnx").path

    /// 640 x 480 RGB wall with a red plate covering raw columns 300..339 and rows 200..259 (40 x 60 px).
    private func redPlateFrame() -> ImageBuffer {
        let width = 640, height = 480
        var pixels = [UInt8](repeating: 120, count: width * height * 3)
        for v in 200..<260 {
            for u in 300..<340 {
                let i = (v * width + u) * 3
                pixels[i] = 220; pixels[i + 1] = 25; pixels[i + 2] = 25
            }
        }
        return ImageBuffer(width: width, height: height, bytesPerRow: width * 3, pixelFormat: .rgb8, data: pixels)
    }

    private func detector(_ catalogue: SignCatalogue) throws -> SignDetector {
        try SignDetector(configuration: DetectorConfiguration(kind: .unet, unetPath: Self.tinyUnet, catalogue: catalogue))
    }

    func testSenseEqualsDetectThenRangeWithTheCatalogueHeight() throws {
        let d = try detector(.defaultCatalogue)
        let frame = redPlateFrame()
        let sensed = try d.sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0.05, rollRad: -Double.pi / 2)
        XCTAssertEqual(sensed.count, 1)
        let s = try XCTUnwrap(sensed.first)
        let detection = try XCTUnwrap(try d.detect(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0.05,
                                                   rollRad: -Double.pi / 2).first)
        let m = SignImageMeasurement(medianBottomRowPx: detection.medianBottomRowPx, medianHeightPx: detection.medianHeightPx,
                                     centerColumnPx: detection.centerColumnPx, bottomEdgeSlope: detection.bottomEdgeSlope,
                                     topEdgeSlope: detection.topEdgeSlope, extentWidthPx: detection.extentWidthPx)
        let camera = UnrolledCamera(fx: detection.unrolledFx, fy: detection.unrolledFy, cx: detection.unrolledCx,
                                    cy: detection.unrolledCy, pitchRad: 0.05, rollRad: detection.appliedRollRad)
        let r = try RangeEstimator.apparentHeight(m, camera: camera, signHeightMeters: 0.21)
        XCTAssertEqual(s.kind, "exit")
        XCTAssertEqual(s.rangeMeters, r.rangeMeters)
        XCTAssertEqual(s.bearingRad, r.bearingRad)
        XCTAssertEqual(s.score, detection.score)
        // 40 px of a 0.21 m face at f = 534 px: about 2.8 m.
        XCTAssertEqual(s.rangeMeters, 0.21 * 534 / 40, accuracy: 0.1)
        // Corners: the plate's raw corners, in the upright sign's TL, TR, BR, BL order (portrait: the sign's top
        // is raw -u... its left raw +v).
        XCTAssertEqual(s.cornersRaw.count, 4)
        let us = s.cornersRaw.map(\.u), vs = s.cornersRaw.map(\.v)
        XCTAssertEqual(us.min()!, 299.5, accuracy: 1.5)
        XCTAssertEqual(us.max()!, 339.5, accuracy: 1.5)
        XCTAssertEqual(vs.min()!, 199.5, accuracy: 2.5)
        XCTAssertEqual(vs.max()!, 259.5, accuracy: 2.5)
    }

    func testTheFaceHeightComesFromTheCatalogue() throws {
        let tall = SignCatalogue(kinds: [SignKindSpec(kind: "exit", heightMeters: 0.42, widthMeters: 0.6)])
        let frame = redPlateFrame()
        let a = try detector(.defaultCatalogue).sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0,
                                                      rollRad: -Double.pi / 2)
        let b = try detector(tall).sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0,
                                         rollRad: -Double.pi / 2)
        XCTAssertEqual(try XCTUnwrap(b.first).rangeMeters / (try XCTUnwrap(a.first).rangeMeters), 2, accuracy: 1e-9)
        // A catalogue without the detector's kind: nothing to range.
        let other = SignCatalogue(kinds: [SignKindSpec(kind: "restroom", heightMeters: 0.2, widthMeters: 0.2)])
        XCTAssertEqual(try detector(other).sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0,
                                                 rollRad: -Double.pi / 2).count, 0)
    }

    func testEmptyOrContradictoryCataloguesAndBadFramesThrowClearErrors() throws {
        let frame = redPlateFrame()
        XCTAssertThrowsError(try detector(SignCatalogue(kinds: [])).sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5,
                                                                          pitchRad: 0, rollRad: 0)) { error in
            guard case SignDetectorError.invalidCatalogue(let message) = error else { return XCTFail("\(error)") }
            XCTAssertTrue(message.contains("catalogue is empty"), message)
        }
        let contradictory = SignCatalogue(kinds: [.defaultExit, SignKindSpec(kind: "exit", heightMeters: 0.3, widthMeters: 0.3)])
        XCTAssertThrowsError(try detector(contradictory)) { error in
            guard case SignDetectorError.invalidCatalogue(let message) = error else { return XCTFail("\(error)") }
            XCTAssertTrue(message.contains("contradicts an earlier entry"), message)
        }
        let d = try detector(.defaultCatalogue)
        for (pitch, fragment) in [(Double.nan, "pitch nan"), (2.0, "pitch 2")] {
            XCTAssertThrowsError(try d.sense(image: frame, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: pitch, rollRad: 0)) {
                guard case SignDetectorError.badFrame(let message) = $0 else { return XCTFail("\($0)") }
                XCTAssertTrue(message.contains(fragment), message)
            }
        }
        var short = frame
        short.data.removeLast(10)  // a buffer shorter than its rows
        XCTAssertThrowsError(try d.sense(image: short, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: 0)) {
            guard case SignDetectorError.badFrame = $0 else { return XCTFail("\($0)") }
        }
        var strided = frame
        strided.bytesPerRow = 640 * 3 + 8  // another buffer's stride: the rows would run past the end
        XCTAssertThrowsError(try d.sense(image: strided, fx: 534, fy: 530, cx: 319.5, cy: 239.5, pitchRad: 0, rollRad: 0)) {
            guard case SignDetectorError.badFrame = $0 else { return XCTFail("\($0)") }
        }
    }
}
