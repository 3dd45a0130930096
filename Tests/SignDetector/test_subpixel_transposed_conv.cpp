// Tests of src/subpixel_transposed_conv: which transposed convolutions the sub-pixel layer takes, and that the
// product U-Net gives the same logits with it as with OpenCV's own Deconvolution layer, at the detector's input
// shapes. (Tests/SignDetector/onnx_parity.py checks both paths against ONNX Runtime.)
#include "subpixel_transposed_conv.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace wf::sign;

namespace {

cv::dnn::LayerParams transposed(int kernel, int stride, int pad, int group = 1) {
    cv::dnn::LayerParams p;
    p.type = "Deconvolution";
    const int k[2] = {kernel, kernel}, s[2] = {stride, stride}, z[4] = {pad, pad, pad, pad};
    p.set("kernel_size", cv::dnn::DictValue::arrayInt(k, 2));
    p.set("stride", cv::dnn::DictValue::arrayInt(s, 2));
    p.set("pad", cv::dnn::DictValue::arrayInt(z, 4));
    p.set("group", group);
    p.blobs.push_back(cv::Mat({4, 3, kernel, kernel}, CV_32F, cv::Scalar(0.5)));
    return p;
}

std::vector<char> productModel() {
    std::ifstream f(std::string(WF_REPO_ROOT) + "/SignDetector/models/sign_unet.onnx", std::ios::binary);
    return std::vector<char>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(SubPixelTransposedConvolution, TakesExactlyTheTwoByTwoStrideTwoCase) {
    EXPECT_TRUE(isSubPixelTransposedConvolution(transposed(2, 2, 0)));
    EXPECT_FALSE(isSubPixelTransposedConvolution(transposed(4, 2, 1)));  // overlapping taps
    EXPECT_FALSE(isSubPixelTransposedConvolution(transposed(2, 1, 0)));
    EXPECT_FALSE(isSubPixelTransposedConvolution(transposed(2, 2, 1)));
    EXPECT_FALSE(isSubPixelTransposedConvolution(transposed(2, 2, 0, 3)));
    cv::dnn::LayerParams adjusted = transposed(2, 2, 0);
    const int one[2] = {1, 1};
    adjusted.set("adj", cv::dnn::DictValue::arrayInt(one, 2));
    EXPECT_FALSE(isSubPixelTransposedConvolution(adjusted));
    cv::dnn::LayerParams noWeights = transposed(2, 2, 0);
    noWeights.blobs.clear();
    EXPECT_FALSE(isSubPixelTransposedConvolution(noWeights));
}

TEST(SubPixelTransposedConvolution, TheProductModelGivesTheSameLogitsAtTheDetectorsShapes) {
    const std::vector<char> model = productModel();
    if (model.empty()) GTEST_SKIP() << "SignDetector/models/sign_unet.onnx is absent";
    cv::dnn::Net fast = readOnnxNet(model.data(), model.size(), true);
    cv::dnn::Net reference = readOnnxNet(model.data(), model.size(), false);
    EXPECT_EQ(countSubPixelLayers(fast), 5);  // the four decoder steps and the head
    EXPECT_EQ(countSubPixelLayers(reference), 0);
    cv::RNG rng(17);
    // The zoom window, a coarse pass, a far band, and the zoom window again (a re-planned shape).
    for (const cv::Size size : {cv::Size(192, 160), cv::Size(448, 320), cv::Size(640, 96), cv::Size(192, 160)}) {
        cv::Mat blob({1, 3, size.height, size.width}, CV_32F);
        rng.fill(blob, cv::RNG::UNIFORM, 0.0, 1.0);
        fast.setInput(blob, "image");
        reference.setInput(blob, "image");
        const cv::Mat a = fast.forward().clone();
        const cv::Mat b = reference.forward().clone();
        ASSERT_EQ(a.size[2], size.height);
        ASSERT_EQ(a.size[3], size.width);
        EXPECT_LE(cv::norm(a, b, cv::NORM_INF), 1e-4 * std::max(1.0, cv::norm(b, cv::NORM_INF))) << size;
    }
}
