// wf_unet_dump: runs an ONNX segmentation model with OpenCV 4.6's cv::dnn as the detector does (sub-pixel
// upsampling: src/subpixel_transposed_conv.hpp) on raw float32 inputs and writes the raw float32 logits, for
// the ONNX Runtime parity check (Tests/SignDetector/onnx_parity.py).
//   wf_unet_dump MODEL.onnx SIZE INPUT.f32 OUTPUT.f32 [--opencv-deconvolution]
// INPUT.f32: 1 x 3 x SIZE x SIZE float32, C order. OUTPUT.f32: the 1 x K x SIZE x SIZE logits, C order.
// --opencv-deconvolution: OpenCV's own Deconvolution layer for the transposed convolutions instead.
#include "subpixel_transposed_conv.hpp"

#include <opencv2/dnn.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    const bool opencvDeconvolution = argc == 6 && std::string(argv[5]) == "--opencv-deconvolution";
    if (argc != 5 && !opencvDeconvolution) {
        std::cerr << "usage: wf_unet_dump MODEL.onnx SIZE INPUT.f32 OUTPUT.f32 [--opencv-deconvolution]\n";
        return 2;
    }
    try {
        const int size = std::stoi(argv[2]);
        const size_t n = size_t(3) * size * size;
        std::vector<float> input(n);
        std::ifstream in(argv[3], std::ios::binary);
        if (!in.read(reinterpret_cast<char*>(input.data()), std::streamsize(n * sizeof(float)))) {
            std::cerr << "wf_unet_dump: cannot read " << n << " floats from " << argv[3] << "\n";
            return 1;
        }
        std::ifstream modelFile(argv[1], std::ios::binary);
        const std::vector<char> model((std::istreambuf_iterator<char>(modelFile)), std::istreambuf_iterator<char>());
        if (model.empty()) {
            std::cerr << "wf_unet_dump: cannot read " << argv[1] << "\n";
            return 1;
        }
        cv::dnn::Net net = wf::sign::readOnnxNet(model.data(), model.size(), !opencvDeconvolution);
        net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
        net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
        const int shape[4] = {1, 3, size, size};
        net.setInput(cv::Mat(4, shape, CV_32F, input.data()), "image");
        cv::Mat out = net.forward().clone();
        CV_Assert(out.isContinuous() && out.type() == CV_32F);
        std::ofstream o(argv[4], std::ios::binary);
        o.write(reinterpret_cast<const char*>(out.ptr<float>()), std::streamsize(out.total() * sizeof(float)));
        std::cout << "shape";
        for (int i = 0; i < out.dims; ++i) std::cout << " " << out.size[i];
        std::cout << "\n";
        return o.good() ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "wf_unet_dump: " << e.what() << "\n";
        return 1;
    }
}
