/// The one error type of the SignDetection module: every non-zero C status of the detector becomes a case,
/// with the message the C side wrote (it names the file or the frame problem).
public enum SignDetectorError: Error, Equatable, Sendable, CustomStringConvertible {
    /// A nil/empty argument or an out-of-range option (WF_STATUS_INVALID_ARGUMENT).
    case invalidArgument(String)
    /// The sign-kind catalogue is empty where sizes are needed, lists a kind twice with different sizes, or
    /// gives a size that is not a positive number of meters (WF_STATUS_INVALID_CATALOGUE).
    case invalidCatalogue(String)
    /// A model file (cascade XML, ONNX, classes.json) is missing or unreadable (WF_STATUS_MODEL_LOAD).
    case modelLoad(String)
    /// The frame was rejected: empty, wrong size for its intrinsics, non-finite intrinsics, pitch or roll,
    /// or pixel data shorter than its description (WF_STATUS_BAD_FRAME).
    case badFrame(String)
    /// An image file could not be read or decoded (WF_STATUS_IMAGE_READ).
    case imageRead(String)
    /// An unexpected failure inside OpenCV (WF_STATUS_INTERNAL).
    case internalFailure(String)

    /// The message naming the problem.
    public var message: String {
        switch self {
        case .invalidArgument(let m), .invalidCatalogue(let m), .modelLoad(let m), .badFrame(let m),
             .imageRead(let m), .internalFailure(let m):
            return m
        }
    }

    public var description: String {
        switch self {
        case .invalidArgument: return "invalid argument: \(message)"
        case .invalidCatalogue: return "invalid sign-kind catalogue: \(message)"
        case .modelLoad: return "model load failed: \(message)"
        case .badFrame: return "bad frame: \(message)"
        case .imageRead: return "image read failed: \(message)"
        case .internalFailure: return "internal failure: \(message)"
        }
    }
}
