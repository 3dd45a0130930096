// Runs an ONNX model with the system OpenCV's dnn module (the version the C++ detector links),
// for the parity check in export_unet.py.
// Usage: onnx_cv_dnn_check model.onnx input.f32 output.f32
//   input.f32: 1 x 3 x 224 x 224 float32 (NCHW, little-endian); output.f32: the "logits" blob.
// Prints the OpenCV version and the output shape; exit status 0 on success, 1 on any error.
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: " << argv[0] << " model.onnx input.f32 output.f32\n";
    return 1;
  }
  try {
    cv::dnn::Net net = cv::dnn::readNetFromONNX(argv[1]);
    const int sizes[4] = {1, 3, 224, 224};
    cv::Mat input(4, sizes, CV_32F);
    std::ifstream in(argv[2], std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(input.ptr<float>()), sizeof(float) * 3 * 224 * 224)) {
      std::cerr << "error: cannot read 1x3x224x224 float32 from " << argv[2] << "\n";
      return 1;
    }
    net.setInput(input, "image");
    cv::Mat out = net.forward("logits");
    std::ofstream o(argv[3], std::ios::binary);
    o.write(reinterpret_cast<const char*>(out.ptr<float>()), sizeof(float) * out.total());
    std::cout << "opencv " << CV_VERSION << " output";
    for (int i = 0; i < out.dims; ++i) std::cout << " " << out.size[i];
    std::cout << "\n";
  } catch (const cv::Exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
