import Foundation
import SessionFormat
import SignDetection

/// The size of the colour image the phone hands the detector, and the intrinsics that go with it. ARKit's
/// `capturedImage` is bi-planar YUV at the capture resolution (1920 x 1440 on most iPhones); the adapter
/// converts it to BGRA (vImage) at this size, because the cascade's colour gate needs colour (a gray frame
/// turns the gate off: 79.9 ms instead of 3.7 ms per VGA frame, docs/benchmarks.md "Cascade with the
/// colour gate") and the U-Net reads RGB. The U-Net keeps the full resolution (its coarse pass, far band and
/// zoom were measured on 1920 x 1440 frames); the cascade gets VGA (its 5 ms target is per VGA frame).
public struct DetectorInputGeometry: Sendable, Equatable {
    /// Capture size, pixels.
    public var captureWidth: Int
    /// Capture height, pixels.
    public var captureHeight: Int
    /// Detector image size, pixels.
    public var width: Int
    /// Detector image height, pixels.
    public var height: Int

    /// Scale from capture to detector pixels (1 = full resolution).
    public var scale: Double { Double(width) / Double(captureWidth) }

    /// The detector image for a capture size, shrunk (aspect kept, rounded to whole pixels) so its long side
    /// is at most `maxLongSidePx`; nil = full size. Nil when the capture size is not positive.
    public init?(captureWidth: Int, captureHeight: Int, maxLongSidePx: Int?) {
        guard captureWidth > 0, captureHeight > 0 else { return nil }
        self.captureWidth = captureWidth
        self.captureHeight = captureHeight
        let long = max(captureWidth, captureHeight)
        if let m = maxLongSidePx, m > 0, m < long {
            let s = Double(m) / Double(long)
            width = max(1, Int((Double(captureWidth) * s).rounded()))
            height = max(1, Int((Double(captureHeight) * s).rounded()))
        } else {
            width = captureWidth
            height = captureHeight
        }
    }

    /// The long-side limit for a sighting source: VGA (640) for the cascade, full size otherwise.
    public static func maxLongSidePx(for source: SightingSource) -> Int? { source == .cascade ? 640 : nil }

    /// Intrinsics of the detector image: focal lengths times the scale, principal point mapped with pixel
    /// centres aligned (u' = (u + 0.5) s - 0.5, as vImageScale and cv::resize sample), size replaced.
    public func scaled(_ k: CameraIntrinsics) -> CameraIntrinsics {
        guard width != captureWidth || height != captureHeight else { return k }
        let sx = Double(width) / Double(captureWidth), sy = Double(height) / Double(captureHeight)
        return CameraIntrinsics(fx: k.fx * sx, fy: k.fy * sy, cx: (k.cx + 0.5) * sx - 0.5, cy: (k.cy + 0.5) * sy - 0.5,
                                width: width, height: height)
    }

    /// Wraps converted BGRA pixels (`bytesPerRow` >= 4 x width) as the detector's image. Throws
    /// `SignDetectorError.badFrame` naming the mismatch when the bytes do not fit this geometry.
    public func bgraImage(bytesPerRow: Int, bytes: [UInt8]) throws -> ImageBuffer {
        let image = ImageBuffer(width: width, height: height, bytesPerRow: bytesPerRow, pixelFormat: .bgra8, data: bytes)
        try image.validate()
        return image
    }
}

/// One ARKit video format as plain numbers (ARConfiguration.VideoFormat: imageResolution, framesPerSecond).
public struct VideoFormatOption: Sendable, Equatable {
    /// Image width, pixels.
    public var width: Int
    /// Image height, pixels.
    public var height: Int
    /// Frames per second.
    public var framesPerSecond: Int

    /// Creates an option.
    public init(width: Int, height: Int, framesPerSecond: Int) {
        self.width = width; self.height = height; self.framesPerSecond = framesPerSecond
    }

    /// The format the phone runs: 30 frames per second (the pipeline's design rate, and the rate the
    /// simulated walks and the battery budget in docs/ios.md assume; ARKit's default 60 Hz doubles the
    /// motion-update cost for no gain in a walk), 4:3, the resolution nearest 1920 x 1440 (the detector's
    /// measured frames). Falls back to the first format when none runs at 30 Hz; nil for no formats.
    public static func preferredIndex(_ formats: [VideoFormatOption]) -> Int? {
        guard !formats.isEmpty else { return nil }
        func cost(_ f: VideoFormatOption) -> (Int, Int, Int) {
            let fourThree = f.width * 3 == f.height * 4 || f.height * 3 == f.width * 4
            return (f.framesPerSecond == 30 ? 0 : 1, fourThree ? 0 : 1, abs(f.width * f.height - 1920 * 1440))
        }
        return formats.indices.min { cost(formats[$0]) < cost(formats[$1]) }
    }
}
