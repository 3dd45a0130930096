/// The one error type of the SignDetection module: every non-zero C status of the detector becomes a case,
/// with the message the C side wrote (it names the file or the frame problem).
public enum SignDetectorError: Error, Equatable, Sendable, CustomStringConvertible {
    /// A nil/empty argument or an out-of-range option (WF_ERR_INVALID_ARGUMENT).
    case invalidArgument(String)
    /// The options version is not supported by the linked C library (WF_ERR_VERSION).
    case unsupportedVersion(String)
    /// A model file (cascade XML, ONNX, classes.json) is missing or unreadable (WF_ERR_MODEL_LOAD).
    case modelLoad(String)
    /// The frame was rejected: empty, wrong size for its intrinsics, non-finite intrinsics, pitch or roll,
    /// or pixel data shorter than its description (WF_ERR_BAD_FRAME).
    case badFrame(String)
    /// An image file could not be read or decoded (WF_ERR_IMAGE_READ).
    case imageRead(String)
    /// An unexpected failure inside OpenCV (WF_ERR_INTERNAL).
    case internalFailure(String)

    /// The message naming the problem.
    public var message: String {
        switch self {
        case .invalidArgument(let m), .unsupportedVersion(let m), .modelLoad(let m), .badFrame(let m),
             .imageRead(let m), .internalFailure(let m):
            return m
        }
    }

    public var description: String {
        switch self {
        case .invalidArgument: return "invalid argument: \(message)"
        case .unsupportedVersion: return "unsupported version: \(message)"
        case .modelLoad: return "model load failed: \(message)"
        case .badFrame: return "bad frame: \(message)"
        case .imageRead: return "image read failed: \(message)"
        case .internalFailure: return "internal failure: \(message)"
        }
    }
}
