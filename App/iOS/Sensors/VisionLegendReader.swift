#if canImport(Vision) && canImport(CoreGraphics) && os(iOS)
import CoreGraphics
import ImageIO
import Foundation
import SignDetection
import Vision
import WayfinderCore

/// Reads the legend of a room-number placard with Vision's text recognizer (VNRecognizeTextRequest, accurate
/// level, no language correction: room numbers are not words), the iPhone's counterpart of the detector's
/// tesseract reader on Linux (SignDetector/src/text_reader.cpp; the iOS build of the C++ library has none).
/// `PipelineOptions.legendReader` calls it for each sighting of a kind that reads text: it cuts the face's
/// bounding box (with a 15 % margin) out of the detector's BGRA frame and returns Vision's best line, or nil.
/// Runs on the pipeline queue, synchronously (a 0.15 m plate is at most a few hundred pixels: a few ms).
enum VisionLegendReader {
    /// Lowest Vision confidence (0...1) of a reading that is kept.
    static let minimumConfidence: Float = 0.5

    static func read(image: ImageBuffer, cornersRaw: [PixelPoint]) -> String? {
        guard image.pixelFormat == .bgra8, cornersRaw.count == 4 else { return nil }
        let us = cornersRaw.map(\.u), vs = cornersRaw.map(\.v)
        guard let u0 = us.min(), let u1 = us.max(), let v0 = vs.min(), let v1 = vs.max(), u1 > u0, v1 > v0 else { return nil }
        let mu = 0.15 * (u1 - u0), mv = 0.15 * (v1 - v0)
        let left = max(0, Int((u0 - mu).rounded(.down))), top = max(0, Int((v0 - mv).rounded(.down)))
        let right = min(image.width, Int((u1 + mu).rounded(.up)) + 1), bottom = min(image.height, Int((v1 + mv).rounded(.up)) + 1)
        guard right - left >= 8, bottom - top >= 8 else { return nil }
        // Copy the crop into its own BGRA buffer and wrap it as a CGImage.
        let width = right - left, height = bottom - top
        var crop = [UInt8](repeating: 0, count: width * height * 4)
        image.data.withUnsafeBufferPointer { src in
            for row in 0..<height {
                let from = (top + row) * image.bytesPerRow + left * 4
                crop.replaceSubrange(row * width * 4..<(row + 1) * width * 4, with: src[from..<(from + width * 4)])
            }
        }
        let info = CGBitmapInfo(rawValue: CGImageAlphaInfo.noneSkipFirst.rawValue | CGBitmapInfo.byteOrder32Little.rawValue)
        guard let provider = CGDataProvider(data: Data(crop) as CFData),
              let cg = CGImage(width: width, height: height, bitsPerComponent: 8, bitsPerPixel: 32, bytesPerRow: width * 4,
                               space: CGColorSpaceCreateDeviceRGB(), bitmapInfo: info, provider: provider, decode: nil,
                               shouldInterpolate: false, intent: .defaultIntent)
        else { return nil }
        let request = VNRecognizeTextRequest()
        request.recognitionLevel = .accurate
        request.usesLanguageCorrection = false
        let handler = VNImageRequestHandler(cgImage: cg, orientation: orientation(cornersRaw), options: [:])
        guard (try? handler.perform([request])) != nil,
              let best = request.results?.compactMap({ $0.topCandidates(1).first }).max(by: { $0.confidence < $1.confidence }),
              best.confidence >= minimumConfidence
        else { return nil }
        return best.string
    }

    /// How the crop must be turned for its text to read upright, from the face's top edge (TL -> TR) in the raw
    /// frame: along +u upright, -u upside down, -v (a portrait frame: world up is raw -u) turned a quarter clockwise
    /// for display (`.right`), +v a quarter counter-clockwise (`.left`).
    static func orientation(_ corners: [PixelPoint]) -> CGImagePropertyOrientation {
        let du = corners[1].u - corners[0].u, dv = corners[1].v - corners[0].v
        if abs(du) >= abs(dv) { return du >= 0 ? .up : .down }
        return dv < 0 ? .right : .left
    }
}
#endif
