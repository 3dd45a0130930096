#if canImport(CoreML) && canImport(Vision) && os(iOS)
import CoreML
import Vision

/// Runs the committed U-Net (SignDetector/models/SignUNet.mlpackage, compiled by Xcode) with Core ML on a
/// 224 x 224 crop of the unrolled frame and returns the per-pixel probability of each sign class, row-major
/// (class, row, column). Slice measurement of the mask happens in the shared C++ detector, as on Linux.
final class CoreMLSegmenter {
    private let model: MLModel

    init() throws {
        guard let url = Bundle.main.url(forResource: "SignUNet", withExtension: "mlmodelc") else {
            throw NSError(domain: "Wayfinder", code: 1, userInfo: [NSLocalizedDescriptionKey: "SignUNet model missing from the app bundle"])
        }
        let configuration = MLModelConfiguration()
        configuration.computeUnits = .all
        model = try MLModel(contentsOf: url, configuration: configuration)
    }

    /// Logits for one 224 x 224 RGB input given as a multi-array (1, 3, 224, 224), values 0...1.
    func logits(for input: MLMultiArray) throws -> MLMultiArray? {
        let provider = try MLDictionaryFeatureProvider(dictionary: ["image": MLFeatureValue(multiArray: input)])
        return try model.prediction(from: provider).featureValue(for: "logits")?.multiArrayValue
    }
}
#endif
