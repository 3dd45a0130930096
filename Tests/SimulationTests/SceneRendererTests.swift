import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// The image renderer: signs where the camera model puts them, floor and ceiling the right way up, PPM output.
final class SceneRendererTests: XCTestCase {
    /// A 4 m wide, 20 m long corridor along +x with an Exit sign on its east end wall, facing west.
    private static let corridor: Floor = Floor(
        id: "1", name: "Test", elevationMeters: 0,
        walls: [Wall(from: Point2(0, 0), to: Point2(20, 0)), Wall(from: Point2(0, 4), to: Point2(20, 4)),
                Wall(from: Point2(20, 0), to: Point2(20, 4)), Wall(from: Point2(0, 0), to: Point2(0, 4))],
        signs: [Sign(id: "s", kind: "exit", position: Point2(20, 2), facing: Point2(-1, 0), widthMeters: 0.3,
                     heightMeters: 0.21, mountingHeightMeters: 2.3)])

    private func renderer(x: Double, yawRad: Double = 0, pitchRad: Double, rollRad: Double, height: Double = 1.4) -> SceneRenderer {
        let state = TrueCameraState(t: 0, floorId: "1", position: Point2Value(x: x, y: 2), altitudeMeters: height,
                                    heightAboveFloorMeters: height, yawRad: yawRad, pitchRad: pitchRad, rollRad: rollRad,
                                    yawRateRadPerSecond: 0)
        let f = Self.corridor
        return SceneRenderer(floors: ["1": f], geometry: ["1": FloorGeometry(walls: f.walls)], states: [state],
                             intrinsics: SceneRenderer.imageIntrinsics, seed: 1)
    }

    /// Bounding box and centroid of the red sign pixels.
    private func redBlob(_ rgb: [UInt8], width: Int, height: Int) -> (minU: Int, maxU: Int, minV: Int, maxV: Int, cu: Double, cv: Double, n: Int) {
        var minU = Int.max, maxU = -1, minV = Int.max, maxV = -1, su = 0.0, sv = 0.0, n = 0
        for v in 0..<height { for u in 0..<width {
            let o = (v * width + u) * 3
            if rgb[o] > 140 && rgb[o + 1] < 90 && rgb[o + 2] < 90 {
                minU = min(minU, u); maxU = max(maxU, u); minV = min(minV, v); maxV = max(maxV, v)
                su += Double(u); sv += Double(v); n += 1
            }
        } }
        return (minU, maxU, minV, maxV, su / Double(max(1, n)), sv / Double(max(1, n)), n)
    }

    func testSignAppearsWhereTheCameraModelProjectsItLandscape() {
        let r = renderer(x: 16, pitchRad: 0.15, rollRad: 0)   // 4 m from the sign
        let rgb = r.render(frameIndex: 0)
        let k = SceneRenderer.imageIntrinsics
        let blob = redBlob(rgb, width: k.width, height: k.height)
        XCTAssertGreaterThan(blob.n, 100)
        let pose = SignObservationModel.mapPose(r.states[0])
        let top = SignObservationModel.project((19.99, 2, 2.51), pose: pose, intrinsics: k)!
        let bottom = SignObservationModel.project((19.99, 2, 2.30), pose: pose, intrinsics: k)!
        let left = SignObservationModel.project((19.99, 2.15, 2.405), pose: pose, intrinsics: k)!
        let right = SignObservationModel.project((19.99, 1.85, 2.405), pose: pose, intrinsics: k)!
        // Landscape upright: the sign is upright, 0.3 m wide and 0.21 m tall at 4 m: ~40 x 28 pixels.
        XCTAssertEqual(Double(blob.maxV - blob.minV + 1), bottom.v - top.v, accuracy: 2)
        XCTAssertEqual(Double(blob.maxU - blob.minU + 1), right.u - left.u, accuracy: 2)
        XCTAssertEqual(Double(blob.minV), top.v, accuracy: 1.5)
        XCTAssertEqual(Double(blob.minU), left.u, accuracy: 1.5)
    }

    func testPortraitImageIsInSensorOrientation() {
        // Held in portrait (roll -90 degrees), the sign lies on its side: taller than wide in the image.
        let r = renderer(x: 16, pitchRad: 0.15, rollRad: -Double.pi / 2)
        let k = SceneRenderer.imageIntrinsics
        let blob = redBlob(r.render(frameIndex: 0), width: k.width, height: k.height)
        XCTAssertGreaterThan(blob.maxV - blob.minV, blob.maxU - blob.minU)
        let pose = SignObservationModel.mapPose(r.states[0])
        let centre = SignObservationModel.project((19.99, 2, 2.405), pose: pose, intrinsics: k)!
        XCTAssertEqual(blob.cu, centre.u, accuracy: 2); XCTAssertEqual(blob.cv, centre.v, accuracy: 2)
        // Looking up (pitch > 0) with roll -90: world up is image -u (to the left), so the ceiling fills the left.
        let leftPixel = (240 * k.width + 5) * 3, rightPixel = (240 * k.width + 634) * 3
        let rgb = r.render(frameIndex: 0)
        XCTAssertGreaterThan(Int(rgb[leftPixel]), Int(rgb[rightPixel]), "ceiling (bright) left, floor (dark) right")
    }

    func testFloorBelowCeilingAboveInLandscape() {
        let r = renderer(x: 2, pitchRad: 0, rollRad: 0)
        let rgb = r.render(frameIndex: 0)
        let k = SceneRenderer.imageIntrinsics
        let top = (3 * k.width + 320) * 3, bottom = ((k.height - 3) * k.width + 320) * 3
        XCTAssertGreaterThan(Int(rgb[top]), Int(rgb[bottom]))
    }

    func testExitTextureAndPPMHeader() {
        XCTAssertEqual(SceneRenderer.exitTexture(s: 0.02, t: 0.5).0, 0.85)               // red rim
        XCTAssertEqual(SceneRenderer.exitTexture(s: 0.5, t: 0.1).1, 0.97)                // white plate
        XCTAssertEqual(SceneRenderer.exitTexture(s: 0.1 + 0.8 * 0.5 / 23, t: 0.5).1, 0.08) // E's stem
        let r = renderer(x: 10, pitchRad: 0, rollRad: 0)
        let data = r.renderPPM(frameIndex: 0)
        XCTAssertEqual(data, r.renderPPM(frameIndex: 0), "deterministic, noise included")
        let header = "P6\n640 480\n255\n"
        XCTAssertEqual(String(decoding: data.prefix(header.utf8.count), as: UTF8.self), header)
        XCTAssertEqual(data.count, header.utf8.count + 640 * 480 * 3)
    }

    func testImagesAreWrittenForTheImageFrames() throws {
        let s = SimulationScenario(name: "img", from: "room-101", to: "room-102", seed: 3, rateHz: 10, images: true, imageRateHz: 2)
        let w = try WalkSimulator.simulate(building: Fixtures.office, scenario: s)
        XCTAssertEqual(w.imageFrameIndices.first, 0)
        XCTAssertEqual(w.imageFrameIndices.dropFirst().first, 5)
        XCTAssertEqual(w.frames[5].image, "frame-000005.ppm"); XCTAssertNil(w.frames[1].image)
        XCTAssertEqual(w.frames[0].intrinsics, SceneRenderer.imageIntrinsics)
        XCTAssertEqual(w.info.intrinsics, SceneRenderer.imageIntrinsics)
    }
}
