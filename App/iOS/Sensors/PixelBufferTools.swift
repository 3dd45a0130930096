#if canImport(CoreVideo) && canImport(CoreImage) && os(iOS)
import CoreImage
import CoreVideo
import SignDetection

/// Reads ARKit's bi-planar YUV pixel buffer without copying the image: mean luma over a sparse grid, and a
/// JPEG only when recording.
enum PixelBufferTools {
    static let context = CIContext()

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

    /// The luma plane as the detector's gray image: one copy of the Y plane (the detector only needs luma
    /// for the cascade, and the U-Net path converts gray to RGB), made only for frames the scheduler sends.
    static func lumaImage(_ buffer: CVPixelBuffer) -> ImageBuffer? {
        CVPixelBufferLockBaseAddress(buffer, .readOnly)
        defer { CVPixelBufferUnlockBaseAddress(buffer, .readOnly) }
        guard let base = CVPixelBufferGetBaseAddressOfPlane(buffer, 0) else { return nil }
        let width = CVPixelBufferGetWidthOfPlane(buffer, 0), height = CVPixelBufferGetHeightOfPlane(buffer, 0)
        let stride = CVPixelBufferGetBytesPerRowOfPlane(buffer, 0)
        let bytes = UnsafeBufferPointer(start: base.assumingMemoryBound(to: UInt8.self), count: stride * height)
        return ImageBuffer(width: width, height: height, bytesPerRow: stride, pixelFormat: .gray8, data: Array(bytes))
    }

    /// JPEG of the frame at quality 0.6 (recording only).
    static func jpeg(_ buffer: CVPixelBuffer) -> Data? {
        let image = CIImage(cvPixelBuffer: buffer)
        guard let space = CGColorSpace(name: CGColorSpace.sRGB) else { return nil }
        return context.jpegRepresentation(of: image, colorSpace: space,
                                          options: [kCGImageDestinationLossyCompressionQuality as CIImageRepresentationOption: 0.6])
    }
}
#endif
