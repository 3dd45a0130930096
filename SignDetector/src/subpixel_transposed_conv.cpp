#include "subpixel_transposed_conv.hpp"

#include <opencv2/dnn/all_layers.hpp>

#include <mutex>

namespace wf::sign {
namespace {

/// Set while readOnnxNet imports with `subPixel`: the factory below consults it (the importer, on this thread,
/// is what instantiates the layers).
thread_local bool tImportSubPixel = false;

bool allEqual(const cv::dnn::LayerParams& p, const char* name, int value, bool missingIsOk) {
    if (!p.has(name)) return missingIsOk;
    const cv::dnn::DictValue& d = p.get(name);
    for (int i = 0; i < d.size(); ++i) {
        if (d.get<int>(i) != value) return false;
    }
    return true;
}

/// y[n, o, 2i + a, 2j + b] = bias[o] + sum_c W[c, o, a, b] x[n, c, i, j], as z = conv1x1(x) with output channel
/// 4 o + 2 a + b, then the depth-to-space copy of z into y.
class SubPixelTransposedConvolution : public cv::dnn::Layer {
public:
    explicit SubPixelTransposedConvolution(const cv::dnn::LayerParams& params) : cv::dnn::Layer(params) {
        const cv::Mat& w = params.blobs[0];  // (in, out, 2, 2)
        inChannels_ = w.size[0];
        outChannels_ = w.size[1];
        const bool hasBias = params.blobs.size() > 1 && params.blobs[1].total() == size_t(outChannels_);
        cv::Mat weights({4 * outChannels_, inChannels_, 1, 1}, CV_32F);
        cv::Mat bias(1, 4 * outChannels_, CV_32F, cv::Scalar(0));
        cv::Mat w32;
        w.convertTo(w32, CV_32F);
        const float* src = w32.ptr<float>();
        for (int o = 0; o < outChannels_; ++o) {
            for (int phase = 0; phase < 4; ++phase) {
                float* dst = weights.ptr<float>() + size_t(4 * o + phase) * inChannels_;
                for (int c = 0; c < inChannels_; ++c) dst[c] = src[(size_t(c) * outChannels_ + o) * 4 + phase];
                if (hasBias) bias.at<float>(4 * o + phase) = params.blobs[1].ptr<float>()[o];
            }
        }
        cv::dnn::LayerParams conv;
        conv.name = params.name + "/sub_pixel_1x1";
        conv.type = "Convolution";
        conv.set("kernel_size", 1);
        conv.set("num_output", 4 * outChannels_);
        conv.set("bias_term", true);
        conv.blobs = {weights, bias};
        conv_ = cv::dnn::ConvolutionLayer::create(conv);
    }

    bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int /*requiredOutputs*/,
                         std::vector<cv::dnn::MatShape>& outputs, std::vector<cv::dnn::MatShape>& internals) const override {
        CV_Assert(inputs.size() == 1 && inputs[0].size() == 4 && inputs[0][1] == inChannels_);
        const cv::dnn::MatShape& s = inputs[0];
        outputs.assign(1, cv::dnn::MatShape{s[0], outChannels_, 2 * s[2], 2 * s[3]});
        internals.assign(1, cv::dnn::MatShape{s[0], 4 * outChannels_, s[2], s[3]});
        return false;
    }

    void finalize(cv::InputArrayOfArrays inputsArr, cv::OutputArrayOfArrays /*outputsArr*/) override {
        std::vector<cv::Mat> inputs;
        inputsArr.getMatVector(inputs);
        std::vector<cv::Mat> phases{cv::Mat({inputs[0].size[0], 4 * outChannels_, inputs[0].size[2], inputs[0].size[3]}, CV_32F)};
        conv_->finalize(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(phases));
    }

    void forward(cv::InputArrayOfArrays inputsArr, cv::OutputArrayOfArrays outputsArr,
                 cv::OutputArrayOfArrays internalsArr) override {
        std::vector<cv::Mat> inputs, outputs, internals;
        inputsArr.getMatVector(inputs);
        outputsArr.getMatVector(outputs);
        internalsArr.getMatVector(internals);
        CV_Assert(inputs[0].type() == CV_32F && internals.size() == 1 && outputs.size() == 1);
        std::vector<cv::Mat> phases{internals[0]}, none;
        conv_->forward(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(phases), cv::OutputArrayOfArrays(none));
        const int batch = inputs[0].size[0], rows = inputs[0].size[2], cols = inputs[0].size[3];
        for (int n = 0; n < batch; ++n) {
            for (int o = 0; o < outChannels_; ++o) {
                float* out = outputs[0].ptr<float>(n, o);
                for (int a = 0; a < 2; ++a) {
                    const float* even = internals[0].ptr<float>(n, 4 * o + 2 * a);     // b = 0
                    const float* odd = internals[0].ptr<float>(n, 4 * o + 2 * a + 1);  // b = 1
                    for (int i = 0; i < rows; ++i) {
                        float* row = out + size_t(2 * i + a) * (2 * cols);
                        const float* e = even + size_t(i) * cols;
                        const float* d = odd + size_t(i) * cols;
                        for (int j = 0; j < cols; ++j) {
                            row[2 * j] = e[j];
                            row[2 * j + 1] = d[j];
                        }
                    }
                }
            }
        }
    }

private:
    int inChannels_ = 0;
    int outChannels_ = 0;
    cv::Ptr<cv::dnn::BaseConvolutionLayer> conv_;
};

cv::Ptr<cv::dnn::Layer> createTransposedConvolution(cv::dnn::LayerParams& params) {
    if (tImportSubPixel && isSubPixelTransposedConvolution(params)) {
        return cv::Ptr<cv::dnn::Layer>(new SubPixelTransposedConvolution(params));
    }
    return cv::dnn::DeconvolutionLayer::create(params);
}

}  // namespace

bool isSubPixelTransposedConvolution(const cv::dnn::LayerParams& p) {
    if (!allEqual(p, "kernel_size", 2, false) || !allEqual(p, "stride", 2, false)) return false;
    if (!allEqual(p, "pad", 0, true) || !allEqual(p, "adj", 0, true) || !allEqual(p, "dilation", 1, true)) return false;
    if (p.has("pad_mode") && !p.get<cv::String>("pad_mode").empty()) return false;
    if (p.get<int>("group", 1) != 1 || p.blobs.empty()) return false;
    const cv::Mat& w = p.blobs[0];
    return w.dims == 4 && w.size[2] == 2 && w.size[3] == 2 && w.size[0] > 0 && w.size[1] > 0;
}

int countSubPixelLayers(cv::dnn::Net& net) {
    int n = 0;
    for (const cv::String& name : net.getLayerNames()) {
        if (dynamic_cast<SubPixelTransposedConvolution*>(net.getLayer(name).get()) != nullptr) ++n;
    }
    return n;
}

cv::dnn::Net readOnnxNet(const char* data, size_t size, bool subPixel) {
    // OpenCV's factory is process-wide: the creator registered here hands every layer it does not take to
    // OpenCV's own Deconvolution, so other importers in the process are unaffected.
    static std::once_flag registered;
    std::call_once(registered, [] { cv::dnn::LayerFactory::registerLayer("Deconvolution", createTransposedConvolution); });
    struct Scope {
        explicit Scope(bool on) { tImportSubPixel = on; }
        ~Scope() { tImportSubPixel = false; }
    } scope(subPixel);
    return cv::dnn::readNetFromONNX(data, size);
}

}  // namespace wf::sign
