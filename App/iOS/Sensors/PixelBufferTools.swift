#if canImport(CoreVideo) && canImport(CoreImage) && canImport(Accelerate) && os(iOS)
import Accelerate
import CoreImage
import CoreVideo
import SignDetection
import WayfinderCore

/// Reads ARKit's bi-planar full-range YUV pixel buffer (`capturedImage`): mean luma over a sparse grid
/// (covered-camera check) on every frame, and for the frames the scheduler sends to the detector a BGRA
/// copy at the detector's size (`DetectorInputGeometry`): colour, because the cascade's colour gate and the
/// U-Net need it (a gray frame costs the cascade 20 x more, docs/benchmarks.md). JPEGs only when recording.
enum PixelBufferTools {
    static let context = CIContext()

    /// YpCbCr -> ARGB conversion for full-range BT.601 (ARKit's kCVPixelFormatType_420YpCbCr8BiPlanarFullRange),
    /// the same matrix as the detector's own NV12 reader (SignDetector/src/image_input.cpp).
    private static let conversion: vImage_YpCbCrToARGB? = {
        var info = vImage_YpCbCrToARGB()
        var range = vImage_YpCbCrPixelRange(Yp_bias: 0, CbCr_bias: 128, YpRangeMax: 255, CbCrRangeMax: 255,
                                            YpMax: 255, YpMin: 0, CbCrMax: 255, CbCrMin: 0)
        let error = vImageConvert_YpCbCrToARGB_GenerateConversion(kvImage_YpCbCrToARGBMatrix_ITU_R_601_4, &range, &info,
                                                                  kvImage420Yp8_CbCr8, kvImageARGB8888, vImage_Flags(kvImageNoFlags))
        return error == kvImageNoError ? info : nil
    }()

    /// Mean of the luma plane sampled every 16th pixel (0...255).
    static func meanLuma(_ buffer: CVPixelBuffer) -> Double? {
        CVPixelBufferLockBaseAddress(buffer, .readOnly)
        defer { CVPixelBufferUnlockBaseAddress(buffer, .readOnly) }
        guard let base = CVPixelBufferGetBaseAddressOfPlane(buffer, 0) else { return nil }
        let width = CVPixelBufferGetWidthOfPlane(buffer, 0), height = CVPixelBufferGetHeightOfPlane(buffer, 0)
        let stride = CVPixelBufferGetBytesPerRowOfPlane(buffer, 0)
        let bytes = base.assumingMemoryBound(to: UInt8.self)
        var sum = 0, count = 0
        for y in Swift.stride(from: 0, to: height, by: 16) {
            for x in Swift.stride(from: 0, to: width, by: 16) { sum += Int(bytes[y * stride + x]); count += 1 }
        }
        return count > 0 ? Double(sum) / Double(count) : nil
    }

    /// The frame as the detector's BGRA image at `geometry`'s size: one vImage conversion (NEON) from the
    /// two planes into a packed buffer, then a vImage scale when the detector takes a smaller image.
    static func bgraImage(_ buffer: CVPixelBuffer, geometry: DetectorInputGeometry) -> ImageBuffer? {
        guard var info = conversion, CVPixelBufferGetPlaneCount(buffer) == 2 else { return nil }
        CVPixelBufferLockBaseAddress(buffer, .readOnly)
        defer { CVPixelBufferUnlockBaseAddress(buffer, .readOnly) }
        guard let yBase = CVPixelBufferGetBaseAddressOfPlane(buffer, 0),
              let cBase = CVPixelBufferGetBaseAddressOfPlane(buffer, 1) else { return nil }
        let w = CVPixelBufferGetWidthOfPlane(buffer, 0), h = CVPixelBufferGetHeightOfPlane(buffer, 0)
        var yPlane = vImage_Buffer(data: yBase, height: vImagePixelCount(h), width: vImagePixelCount(w),
                                   rowBytes: CVPixelBufferGetBytesPerRowOfPlane(buffer, 0))
        var cPlane = vImage_Buffer(data: cBase, height: vImagePixelCount(h / 2), width: vImagePixelCount(w / 2),
                                   rowBytes: CVPixelBufferGetBytesPerRowOfPlane(buffer, 1))
        var full = [UInt8](repeating: 0, count: w * h * 4)
        let bgraOrder: [UInt8] = [3, 2, 1, 0]   // ARGB -> BGRA
        let converted: vImage_Error = full.withUnsafeMutableBytes { raw in
            var out = vImage_Buffer(data: raw.baseAddress, height: vImagePixelCount(h), width: vImagePixelCount(w), rowBytes: w * 4)
            return vImageConvert_420Yp8_CbCr8ToARGB8888(&yPlane, &cPlane, &out, &info, bgraOrder, 255, vImage_Flags(kvImageNoFlags))
        }
        guard converted == kvImageNoError else { return nil }
        if geometry.width == w && geometry.height == h { return try? geometry.bgraImage(bytesPerRow: w * 4, bytes: full) }
        var small = [UInt8](repeating: 0, count: geometry.width * geometry.height * 4)
        let scaled: vImage_Error = full.withUnsafeMutableBytes { src in
            small.withUnsafeMutableBytes { dst in
                var s = vImage_Buffer(data: src.baseAddress, height: vImagePixelCount(h), width: vImagePixelCount(w), rowBytes: w * 4)
                var d = vImage_Buffer(data: dst.baseAddress, height: vImagePixelCount(geometry.height),
                                      width: vImagePixelCount(geometry.width), rowBytes: geometry.width * 4)
                return vImageScale_ARGB8888(&s, &d, nil, vImage_Flags(kvImageNoFlags))
            }
        }
        guard scaled == kvImageNoError else { return nil }
        return try? geometry.bgraImage(bytesPerRow: geometry.width * 4, bytes: small)
    }

    /// JPEG of the frame at the detector's size, quality 0.6 (recording only), so a recorded frame's image
    /// and intrinsics agree.
    static func jpeg(_ buffer: CVPixelBuffer, geometry: DetectorInputGeometry) -> Data? {
        var image = CIImage(cvPixelBuffer: buffer)
        if geometry.scale != 1 { image = image.transformed(by: CGAffineTransform(scaleX: geometry.scale, y: geometry.scale)) }
        guard let space = CGColorSpace(name: CGColorSpace.sRGB) else { return nil }
        return context.jpegRepresentation(of: image, colorSpace: space,
                                          options: [kCGImageDestinationLossyCompressionQuality as CIImageRepresentationOption: 0.6])
    }
}
#endif
