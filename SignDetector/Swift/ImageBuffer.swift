/// Pixel layout of an ImageBuffer (mirrors the C side's wf_pixel_format).
public enum PixelFormat: String, Sendable, CaseIterable {
    /// 8-bit luma, 1 byte per pixel.
    case gray8
    /// 8-bit B, G, R, A (a kCVPixelFormatType_32BGRA pixel buffer), 4 bytes per pixel.
    case bgra8
    /// 8-bit R, G, B, 3 bytes per pixel.
    case rgb8
    /// Bi-planar 4:2:0 full-range YCbCr as ARKit's capturedImage delivers: `data` is the Y plane,
    /// `chromaData` the interleaved CbCr plane (nil: processed as gray).
    case nv12

    /// Bytes per pixel of the first plane.
    public var bytesPerPixel: Int {
        switch self {
        case .gray8, .nv12: return 1
        case .rgb8: return 3
        case .bgra8: return 4
        }
    }
}

/// An image owned by Swift: `height` rows of `bytesPerRow` bytes in `data` (plus the chroma plane for
/// NV12). A value type; the detector only borrows its bytes during a call.
public struct ImageBuffer: Sendable, Equatable {
    /// Size in pixels.
    public var width: Int
    public var height: Int
    /// Bytes from one row to the next in `data` (>= width * bytesPerPixel).
    public var bytesPerRow: Int
    /// Layout of `data`.
    public var pixelFormat: PixelFormat
    /// Pixels (for NV12: the Y plane).
    public var data: [UInt8]
    /// NV12 only: bytes per row of the interleaved CbCr plane.
    public var chromaBytesPerRow: Int
    /// NV12 only: the interleaved CbCr plane ((height + 1) / 2 rows), or nil.
    public var chromaData: [UInt8]?

    /// Wraps pixels; nothing is validated until the buffer is used (`validate()`).
    public init(width: Int, height: Int, bytesPerRow: Int, pixelFormat: PixelFormat, data: [UInt8],
                chromaBytesPerRow: Int = 0, chromaData: [UInt8]? = nil) {
        self.width = width
        self.height = height
        self.bytesPerRow = bytesPerRow
        self.pixelFormat = pixelFormat
        self.data = data
        self.chromaBytesPerRow = chromaBytesPerRow
        self.chromaData = chromaData
    }

    /// A tightly packed 8-bit gray image.
    public static func gray(width: Int, height: Int, pixels: [UInt8]) -> ImageBuffer {
        ImageBuffer(width: width, height: height, bytesPerRow: width, pixelFormat: .gray8, data: pixels)
    }

    /// Reads and decodes an image file (PNG, JPEG, BMP...) with the C side's cv::imread, converted to
    /// `pixelFormat` (.gray8, .rgb8 or .bgra8). Throws `SignDetectorError.imageRead` naming the file.
    public static func load(path: String, pixelFormat: PixelFormat = .rgb8) throws -> ImageBuffer {
        try CDetector.readImage(path: path, pixelFormat: pixelFormat)
    }

    /// Checks that the description fits the bytes (the C side reads `data` by this description).
    /// Throws `SignDetectorError.badFrame` naming the mismatch.
    public func validate() throws {
        guard width > 0, height > 0 else {
            throw SignDetectorError.badFrame("empty frame: size \(width)x\(height)")
        }
        guard bytesPerRow >= width * pixelFormat.bytesPerPixel else {
            throw SignDetectorError.badFrame(
                "row stride \(bytesPerRow) bytes is smaller than width \(width) x \(pixelFormat.bytesPerPixel) bytes per pixel")
        }
        let needed = bytesPerRow * (height - 1) + width * pixelFormat.bytesPerPixel
        guard data.count >= needed else {
            throw SignDetectorError.badFrame("image data has \(data.count) bytes; \(width)x\(height) \(pixelFormat.rawValue) with \(bytesPerRow) bytes per row needs \(needed)")
        }
        if pixelFormat == .nv12, let chroma = chromaData {
            let pairs = 2 * ((width + 1) / 2)
            let rows = (height + 1) / 2
            guard chromaBytesPerRow >= pairs, chroma.count >= chromaBytesPerRow * (rows - 1) + pairs else {
                throw SignDetectorError.badFrame("NV12 chroma plane has \(chroma.count) bytes with \(chromaBytesPerRow) bytes per row; needs \(rows) rows of \(pairs) bytes")
            }
        }
    }
}
