import Foundation

/// A grayscale raster read from a Windows BMP file; row 0 is the TOP row of the picture.
public struct GrayImage: Sendable {
    /// Columns.
    public let width: Int
    /// Rows.
    public let height: Int
    /// Luma 0...255, row-major from the top-left pixel.
    public let pixels: [UInt8]
    /// Luma of the pixel at `column`, `row` (row 0 = top).
    public subscript(column: Int, row: Int) -> UInt8 { pixels[row * width + column] }
}

/// Why a BMP file could not be read.
public struct BMPError: Error, CustomStringConvertible, Sendable {
    /// The file's path or name.
    public let file: String
    /// What is wrong.
    public let reason: String
    /// `file: reason`.
    public var description: String { "\(file): \(reason)" }
}

/// Minimal BMP reader (Microsoft "BITMAPINFOHEADER" family): uncompressed 1-, 4- and 8-bit palettized,
/// 24-bit BGR and 32-bit BGRX; bottom-up (positive height) or top-down (negative height) rows, each row
/// padded to a multiple of 4 bytes. Colour is reduced to luma (0.299 R + 0.587 G + 0.114 B).
/// Layout reference: Microsoft documentation of BITMAPFILEHEADER / BITMAPINFOHEADER.
public enum BMPReader {
    /// Reads the BMP at `url`.
    /// - Throws: `BMPError` naming the file for a missing, truncated or unsupported file.
    public static func read(contentsOf url: URL) throws -> GrayImage {
        guard let data = try? Data(contentsOf: url) else {
            throw BMPError(file: url.path, reason: FileManager.default.fileExists(atPath: url.path) ? "cannot read the file" : "no such file")
        }
        return try decode(data, file: url.path)
    }

    /// Decodes BMP bytes; `file` names the source in errors.
    /// - Throws: `BMPError`.
    public static func decode(_ data: Data, file: String) throws -> GrayImage {
        let b = [UInt8](data)
        func fail(_ r: String) -> BMPError { BMPError(file: file, reason: r) }
        func u16(_ o: Int) -> Int { Int(b[o]) | Int(b[o + 1]) << 8 }
        func u32(_ o: Int) -> UInt32 { UInt32(b[o]) | UInt32(b[o + 1]) << 8 | UInt32(b[o + 2]) << 16 | UInt32(b[o + 3]) << 24 }
        guard b.count >= 54 else { throw fail("not a BMP file (only \(b.count) bytes)") }
        guard b[0] == UInt8(ascii: "B"), b[1] == UInt8(ascii: "M") else { throw fail("not a BMP file (no 'BM' signature)") }
        let pixelOffset = Int(u32(10))
        let dibSize = Int(u32(14))
        guard dibSize >= 40 else { throw fail("unsupported BMP header (size \(dibSize); only BITMAPINFOHEADER and later)") }
        let width = Int(Int32(bitPattern: u32(18)))
        let rawHeight = Int(Int32(bitPattern: u32(22)))
        let bpp = u16(28)
        let compression = u32(30)
        var colorsUsed = Int(u32(46))
        guard width > 0, rawHeight != 0, width <= 65_536, abs(rawHeight) <= 65_536 else {
            throw fail("bad image size \(width) x \(rawHeight)")
        }
        let height = abs(rawHeight)
        let topDown = rawHeight < 0
        guard [1, 4, 8, 24, 32].contains(bpp) else { throw fail("unsupported \(bpp) bits per pixel (1, 4, 8, 24 or 32 supported)") }
        guard compression == 0 || (compression == 3 && bpp == 32) else {
            throw fail("compressed BMP (compression \(compression)) is not supported")
        }
        var palette: [UInt8] = []
        if bpp <= 8 {
            if colorsUsed == 0 { colorsUsed = 1 << bpp }
            let start = 14 + dibSize
            guard colorsUsed <= 256, start + 4 * colorsUsed <= b.count else { throw fail("truncated palette") }
            for i in 0..<colorsUsed {
                let o = start + 4 * i
                palette.append(luma(r: b[o + 2], g: b[o + 1], b: b[o]))
            }
        }
        let stride = ((bpp * width + 31) / 32) * 4
        guard pixelOffset >= 14 + dibSize, pixelOffset + stride * height <= b.count else {
            throw fail("truncated pixel data (needs \(pixelOffset + stride * height) bytes, file has \(b.count))")
        }
        var out = [UInt8](repeating: 0, count: width * height)
        for fileRow in 0..<height {
            let row = topDown ? fileRow : height - 1 - fileRow
            let base = pixelOffset + fileRow * stride
            for c in 0..<width {
                let v: UInt8
                switch bpp {
                case 24, 32:
                    let o = base + c * (bpp / 8)
                    v = luma(r: b[o + 2], g: b[o + 1], b: b[o])
                default:
                    let bit = c * bpp
                    let byte = b[base + bit / 8]
                    let shift = 8 - bpp - (bit % 8)
                    let index = Int((byte >> UInt8(shift)) & UInt8((1 << bpp) - 1))
                    guard index < palette.count else { throw fail("pixel (\(c), \(row)) uses colour \(index) beyond the palette") }
                    v = palette[index]
                }
                out[row * width + c] = v
            }
        }
        return GrayImage(width: width, height: height, pixels: out)
    }

    static func luma(r: UInt8, g: UInt8, b: UInt8) -> UInt8 {
        let rr: Double = 0.299 * Double(r)
        let gg: Double = 0.587 * Double(g)
        let bb: Double = 0.114 * Double(b)
        return UInt8(min(255, (rr + gg + bb).rounded()))
    }

    /// Encodes an 8-bit grayscale BMP (bottom-up, palettized); for tests and tools.
    public static func encodeGray(_ image: GrayImage) -> Data {
        let stride = ((8 * image.width + 31) / 32) * 4
        let pixelOffset = 14 + 40 + 1024
        var b = [UInt8]()
        func put16(_ v: Int) { for k in 0..<2 { b.append(UInt8((v >> (8 * k)) & 0xFF)) } }
        func put32(_ v: Int) { for k in 0..<4 { b.append(UInt8((v >> (8 * k)) & 0xFF)) } }
        b += [UInt8(ascii: "B"), UInt8(ascii: "M")]
        put32(pixelOffset + stride * image.height); put32(0); put32(pixelOffset)
        put32(40); put32(image.width); put32(image.height); put16(1); put16(8); put32(0)
        put32(stride * image.height); put32(2835); put32(2835); put32(256); put32(0)
        for i in 0..<256 { b += [UInt8(i), UInt8(i), UInt8(i), 0] }
        for fileRow in 0..<image.height {
            let row = image.height - 1 - fileRow
            b += image.pixels[(row * image.width)..<((row + 1) * image.width)]
            b += [UInt8](repeating: 0, count: stride - image.width)
        }
        return Data(b)
    }
}
