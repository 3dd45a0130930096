import Foundation
import XCTest
import Maps
@testable import SignDetection

/// Tests of the sign kinds beyond the Exit sign in the Swift wrapper (docs/sign-detection.md "More sign kinds"):
/// the placement band a kind's mounting height gives, the bundled configuration's extra cascades, and the
/// catalogue fields reaching the C++ detector.
final class MoreSignKindsTests: XCTestCase {
    private static let repoRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent()
        .deletingLastPathComponent().deletingLastPathComponent()
    private static let referenceCascade = repoRoot.deletingLastPathComponent()
        .appendingPathComponent("shared/data/skeri_inavigate/models/exit_sign_cascade.xml").path

    func testThePlacementBandComesFromTheMountingHeightForAPhone1To17MetresUp() throws {
        let placard = SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15, mountingHeightMeters: 1.35)
        let band = try XCTUnwrap(DetectorConfiguration.placementBand(placard))
        // Centre 1.425 m above the floor: 1.7 m up it is 0.275 m below the phone, 1.0 m up 0.425 m above; 0.1 m margin.
        XCTAssertEqual(band.lowerBound, 1.425 - 1.8, accuracy: 1e-12)
        XCTAssertEqual(band.upperBound, 1.425 - 0.9, accuracy: 1e-12)
        XCTAssertNil(DetectorConfiguration.placementBand(.defaultExit), "Exit signs keep the detector's own placement")
    }

    func testTheBundledConfigurationAddsTheCascadesOfTheCataloguesOtherKinds() throws {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-kinds-\(UUID().uuidString)").path
        try FileManager.default.createDirectory(atPath: dir, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(atPath: dir) }
        for name in ["exit_sign_cascade.xml", "restroom_cascade.xml", "placard_cascade.xml"] {
            FileManager.default.createFile(atPath: dir + "/" + name, contents: Data("x".utf8))
        }
        FileManager.default.createFile(atPath: dir + "/classes.json", contents: Data(#"{"classes":["background","exit"]}"#.utf8))
        let catalogue = SignCatalogue(kinds: [.defaultExit,
                                              SignKindSpec(kind: "restroom", heightMeters: 0.23, widthMeters: 0.23),
                                              SignKindSpec(kind: "stairs", heightMeters: 0.23, widthMeters: 0.23),
                                              SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15)])
        let cascade = DetectorConfiguration.bundled(kind: .cascade, modelsDirectory: dir, catalogue: catalogue)
        XCTAssertEqual(cascade.cascades.map(\.kind), ["exit", "restroom", "placard"], "stairs has no model file: left out")
        XCTAssertEqual(cascade.cascades[1].path, dir + "/restroom_cascade.xml")
        let unet = DetectorConfiguration.bundled(kind: .unet, modelsDirectory: dir, catalogue: catalogue)
        XCTAssertEqual(unet.cascades.map(\.kind), ["restroom", "placard"], "beside the U-Net: the kinds it has no class for")
        // A U-Net with the wall kinds as classes needs no cascade beside it.
        FileManager.default.createFile(atPath: dir + "/classes.json", contents: Data(
            #"{"classes":["background","exit","restroom","elevator","stairs","placard"]}"#.utf8))
        let multiClass = DetectorConfiguration.bundled(kind: .unet, modelsDirectory: dir, catalogue: catalogue)
        XCTAssertEqual(multiClass.classNames, ["background", "exit", "restroom", "elevator", "stairs", "placard"])
        XCTAssertEqual(multiClass.cascades.map(\.kind), [], "every kind of the catalogue with a model is a class")
        let exitOnly = DetectorConfiguration.bundled(kind: .cascade, modelsDirectory: dir)
        XCTAssertEqual(exitOnly.cascades.map(\.kind), ["exit"])
    }

    /// The catalogue's band reaches the detector: a kind whose band holds the drawn sign sees it, one whose band is
    /// 2 m higher does not (the reference Exit cascade stands in for a pictogram cascade: white on blue is not
    /// Exit-like, so it is searched on its band without the colour gate).
    func testAKindsMountingHeightDecidesWhereItsCascadeLooks() throws {
        try XCTSkipUnless(FileManager.default.fileExists(atPath: Self.referenceCascade), "needs ../shared")
        let frame = try drawnSignFrame()
        func sightings(mountingHeightMeters: Double) throws -> [SensedSign] {
            let kind = SignKindSpec(kind: "restroom", heightMeters: 0.21, widthMeters: 0.33, faceColor: "blue",
                                    legendColor: "white", mountingHeightMeters: mountingHeightMeters)
            var config = DetectorConfiguration(kind: .cascade, cascadePath: Self.referenceCascade, cascadeKind: "restroom",
                                               catalogue: SignCatalogue(kinds: [kind]))
            config.cascadeMinNeighbors = 1
            let detector = try SignDetector(configuration: config)
            return try detector.sense(image: frame.image, fx: frame.f, fy: frame.f, cx: 239.5, cy: 319.5,
                                      pitchRad: 0, rollRad: 0)
        }
        // The sign's centre is 1.5 m above the floor for a phone 1.35 m up (the middle of the 1.0-1.7 m band).
        let seen = try sightings(mountingHeightMeters: 1.5 - 0.105)
        XCTAssertEqual(seen.first?.kind, "restroom")
        XCTAssertEqual(seen.first?.rangeMeters ?? 0, 2.5, accuracy: 0.3)
        XCTAssertNil(seen.first?.text)
        XCTAssertTrue(try sightings(mountingHeightMeters: 3.5).isEmpty)
    }

    /// `senseFrame` says which kinds a frame did not look for: two wall kinds, searched together on every second
    /// frame (the detector's default schedule), and every kind on a frame too dark to search.
    func testSenseFrameSaysWhichKindsTheFrameDidNotLookFor() throws {
        try XCTSkipUnless(FileManager.default.fileExists(atPath: Self.referenceCascade), "needs ../shared")
        let frame = try drawnSignFrame()
        func kind(_ name: String) -> SignKindSpec {
            SignKindSpec(kind: name, heightMeters: 0.21, widthMeters: 0.33, faceColor: "blue", legendColor: "white",
                         mountingHeightMeters: 1.5 - 0.105)
        }
        var config = DetectorConfiguration(kind: .cascade, cascadePath: Self.referenceCascade, cascadeKind: "restroom",
                                           catalogue: SignCatalogue(kinds: [kind("restroom"), kind("stairs")]))
        config.cascades.append(CascadeModel(kind: "stairs", path: Self.referenceCascade))
        config.cascadeMinNeighbors = 1
        let detector = try SignDetector(configuration: config)
        func sensed(_ image: ImageBuffer) throws -> SensedFrame {
            try detector.senseFrame(image: image, fx: frame.f, fy: frame.f, cx: 239.5, cy: 319.5, pitchRad: 0, rollRad: 0)
        }
        let first = try sensed(frame.image), second = try sensed(frame.image), third = try sensed(frame.image)
        XCTAssertEqual(first.unsearchedKinds, [])
        XCTAssertEqual(Set(first.signs.map(\.kind)), ["restroom", "stairs"])
        XCTAssertEqual(second.unsearchedKinds, ["restroom", "stairs"])
        XCTAssertTrue(second.signs.isEmpty)
        XCTAssertEqual(third.unsearchedKinds, [])
        // The caller chooses a frame's wall kinds (the pipeline's WallKindScheduler), on a frame the schedule skips.
        XCTAssertEqual(detector.wallKinds, ["restroom", "stairs"])
        try detector.requestWallKinds(["stairs"])
        let chosen = try sensed(frame.image)
        XCTAssertEqual(chosen.unsearchedKinds, ["restroom"])
        XCTAssertEqual(Set(chosen.signs.map(\.kind)), ["stairs"])
        XCTAssertThrowsError(try detector.requestWallKinds(["exit"])) { error in
            guard case SignDetectorError.invalidArgument = error else { return XCTFail("\(error)") }
        }
        XCTAssertEqual(try sensed(frame.image).unsearchedKinds, ["restroom", "stairs"])  // the schedule's own skip
        let dark = ImageBuffer(width: 480, height: 640, bytesPerRow: 480 * 3, pixelFormat: .rgb8,
                               data: [UInt8](repeating: 0, count: 480 * 640 * 3))
        let skipped = try sensed(dark)
        XCTAssertNotNil(skipped.warning)
        XCTAssertEqual(skipped.unsearchedKinds, ["restroom", "stairs"])
    }

    /// An upright 480 x 640 RGB frame (roll 0, focal 534 px) of a mid-gray wall with a red-on-white "EXIT" face,
    /// 0.33 x 0.21 m, 2.5 m ahead, its centre 0.15 m above the camera.
    private func drawnSignFrame() throws -> (image: ImageBuffer, f: Double) {
        let width = 480, height = 640, f = 534.0
        var pixels = [UInt8](repeating: 128, count: width * height * 3)
        let faceW = Int((0.33 * f / 2.5).rounded()), faceH = Int((0.21 * f / 2.5).rounded())
        let u0 = width / 2 - faceW / 2, v0 = Int((319.5 - 0.15 * f / 2.5).rounded()) - faceH / 2
        // White plate with four red letter blocks and gaps (a cascade-friendly stand-in for "EXIT").
        for v in v0..<(v0 + faceH) {
            for u in u0..<(u0 + faceW) {
                let x = Double(u - u0) / Double(faceW), y = Double(v - v0) / Double(faceH)
                let letter = y > 0.25 && y < 0.75 && x > 0.08 && x < 0.92 && Int((x - 0.08) / 0.21 * 2) % 2 == 0
                let i = (v * width + u) * 3
                pixels[i] = letter ? 210 : 240; pixels[i + 1] = letter ? 30 : 240; pixels[i + 2] = letter ? 30 : 240
            }
        }
        return (ImageBuffer(width: width, height: height, bytesPerRow: width * 3, pixelFormat: .rgb8, data: pixels), f)
    }
}
