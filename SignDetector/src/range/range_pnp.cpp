// PnP range baseline: the sign's pose from its four corners with OpenCV (IPPE, then Levenberg-Marquardt),
// the translation rotated to the gravity-aligned world for a horizontal range.
#include "range_geometry.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace wf::range {

Status estimatePnP(const Corners &corners, const Intrinsics &k, const Eigen::Matrix3d &cameraToWorld,
                   double signWidthMeters, double signHeightMeters, RangeBearing *out) {
    if (std::isnan(signWidthMeters)) return WF_STATUS_MISSING_INPUT;
    if (!std::isfinite(signWidthMeters) || !std::isfinite(signHeightMeters)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(signWidthMeters > 0) || !(signHeightMeters > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    if (const Status s = checkIntrinsics(k); s != WF_STATUS_OK) return s;
    if (const Status s = checkCorners(corners); s != WF_STATUS_OK) return s;

    // Sign frame: x right, y up, z out of the face toward the viewer; the face is the plane z = 0 (IPPE
    // needs a planar target with z = 0).
    const double w = 0.5 * signWidthMeters, h = 0.5 * signHeightMeters;
    const std::vector<cv::Point3d> object = {{-w, h, 0}, {w, h, 0}, {w, -h, 0}, {-w, -h, 0}};
    std::vector<cv::Point2d> image;
    for (const auto &c : corners) image.emplace_back(c.x(), c.y());
    const cv::Matx33d cameraMatrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    // A planar target has a two-fold pose ambiguity, and OpenCV 4.6's IPPE does not always rank its two
    // solutions right (it returned the wrong one on exact corners of a sign 2 m ahead in our tests). So:
    // both IPPE solutions and SQPnP's, each refined with Levenberg-Marquardt, keep the lowest reprojection
    // error among those with the sign in front of the camera.
    std::vector<cv::Mat> rvecs, tvecs;
    cv::solvePnPGeneric(object, image, cameraMatrix, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
    {
        cv::Mat r, t;
        if (cv::solvePnP(object, image, cameraMatrix, cv::noArray(), r, t, false, cv::SOLVEPNP_SQPNP)) {
            rvecs.push_back(r);
            tvecs.push_back(t);
        }
    }
    cv::Mat rvec, tvec;
    double bestError = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < rvecs.size(); ++i) {
        cv::Mat r = rvecs[i].clone(), t = tvecs[i].clone();
        cv::solvePnPRefineLM(object, image, cameraMatrix, cv::noArray(), r, t);
        if (!(t.at<double>(2) > 0)) continue;
        std::vector<cv::Point2d> reprojected;
        cv::projectPoints(object, r, t, cameraMatrix, cv::noArray(), reprojected);
        double error = 0;
        for (std::size_t j = 0; j < image.size(); ++j) error += cv::norm(reprojected[j] - image[j]);
        if (error < bestError) {
            bestError = error;
            rvec = r;
            tvec = t;
        }
    }
    if (tvec.empty()) return WF_STATUS_PNP_FAILED;
    const cv::Vec3d t(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    // OpenCV camera: x right, y down, z forward; ours: x right, y up, looking along -z.
    if (!(t[2] > 0) || !std::isfinite(t[0]) || !std::isfinite(t[1]) || !std::isfinite(t[2]))
        return WF_STATUS_PNP_FAILED;
    const Eigen::Vector3d centerInCamera(t[0], -t[1], -t[2]);
    const Eigen::Vector3d centerInWorld = cameraToWorld * centerInCamera;
    const double range = std::hypot(centerInWorld.x(), centerInWorld.z());
    double bearing = 0;
    if (!(range > 0) || !bearingFromForward(cameraToWorld, centerInWorld, &bearing))
        return WF_STATUS_DEGENERATE_GEOMETRY;
    out->rangeMeters = range;
    out->bearingRad = bearing;
    out->centerHeightAboveCameraMeters = centerInWorld.y();
    return WF_STATUS_OK;
}

}  // namespace wf::range
