// A faster cv::dnn layer for the U-Net's upsampling steps: a 2 x 2 transposed convolution with stride 2 (the
// ONNX ConvTranspose of train_unet.py's decoder and head) computed as a 1 x 1 convolution to four times the
// output channels followed by a depth-to-space copy. With kernel = stride = 2 and no padding, each output pixel
// receives exactly one kernel tap, so the four output phases (row and column parity) are four 1 x 1
// convolutions of the input: the "sub-pixel convolution" of Shi et al., "Real-Time Single Image and Video
// Super-Resolution Using an Efficient Sub-Pixel Convolutional Neural Network" (CVPR 2016). The same sums in
// another order (largest difference from OpenCV's own layer about 3e-6 of logits up to 10).
//
// Why by hand: OpenCV 4.6's Deconvolution layer runs a general col2im scatter that costs 3-4 x its
// multiply-adds at these shapes (5 of the network's 25 ms at 448 x 320 on one core: docs/benchmarks.md
// "Seventeenth stop"), and its ONNX importer turns DepthToSpace into a Permute that is slower still. The 1 x 1
// convolution is OpenCV's own ConvolutionLayer (its vectorised kernels); only the copy is written here.
#pragma once

#include <opencv2/dnn.hpp>

#include <cstddef>

namespace wf::sign {

/// Reads an ONNX model from memory (`data`, `size` bytes, borrowed) into a cv::dnn::Net. With `subPixel`, every
/// ConvTranspose with a 2 x 2 kernel, stride 2, no padding, dilation 1 and one group becomes the sub-pixel
/// layer above; any other one, and every layer with `subPixel` false, is OpenCV's own. The choice is made
/// here, at import (cv::dnn instantiates the layers while importing), so it holds for the Net's lifetime.
/// Throws cv::Exception as cv::dnn::readNetFromONNX does.
cv::dnn::Net readOnnxNet(const char* data, size_t size, bool subPixel);

/// True when cv::dnn layer parameters describe a transposed convolution the sub-pixel layer computes exactly
/// (kernel 2 x 2, stride 2, no padding or output adjustment, dilation 1, one group, 4-D weights).
bool isSubPixelTransposedConvolution(const cv::dnn::LayerParams& params);

/// How many of `net`'s layers are the sub-pixel layer (diagnostics and tests).
int countSubPixelLayers(cv::dnn::Net& net);

}  // namespace wf::sign
