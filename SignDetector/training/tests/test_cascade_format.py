"""The cascade trainer's MB-LBP features, stump semantics and XML writer agree with OpenCV's own
LBP cascade evaluator (cv2.CascadeClassifier), bit for bit, on random stumps and random windows."""
import os
import sys
import tempfile

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import train_cascade as tc  # noqa: E402


def _random_cascade(rng, n_feat):
    stages = []
    for _ in range(3):
        s = tc.Stage()
        for _ in range(4):
            s.stumps.append(tc.Stump(int(rng.integers(n_feat)), rng.random(256) < 0.5,
                                     rng.uniform(-1, 0), rng.uniform(0, 1)))
        s.threshold = float(rng.uniform(-0.6, 0.6))
        stages.append(s)
    return stages


def test_numpy_evaluator_matches_opencv():
    rng = np.random.default_rng(3)
    rects = tc.enumerate_features()
    patches = rng.integers(0, 256, (400, tc.WIN_H, tc.WIN_W)).astype(np.uint8)
    patches[:200] = cv2.GaussianBlur(patches[:200].transpose(1, 2, 0), (5, 5), 2).transpose(2, 0, 1)
    X = tc.compute_features(patches)
    assert X.shape == (400, len(rects))
    with tempfile.TemporaryDirectory() as d:
        for trial in range(3):
            stages = _random_cascade(rng, len(rects))
            path = os.path.join(d, "c%d.xml" % trial)
            tc.write_xml(path, stages, rects, 0.995, 0.5, 100)
            cc = cv2.CascadeClassifier(path)
            assert not cc.empty()
            ours = tc.cascade_pass(stages, X)
            theirs = np.array([len(cc.detectMultiScale(p, scaleFactor=1.5, minNeighbors=0, minSize=(tc.WIN_W, tc.WIN_H),
                                                       maxSize=(tc.WIN_W, tc.WIN_H))) > 0 for p in patches])
            # stage sums within float rounding of a threshold may differ; allow none on random data
            assert (ours == theirs).mean() >= 0.995, (ours != theirs).sum()
            assert 0 < ours.sum() < len(ours)
            # round trip through the reader
            stages2, rects2 = tc.read_xml(path)
            used = sorted({st.feature for s in stages for st in s.stumps})
            X2 = X[:, used]
            assert (tc.cascade_pass(stages2, X2) == ours).all()


if __name__ == "__main__":
    test_numpy_evaluator_matches_opencv()
    print("ok")


def test_detection_windows_and_stump_cost():
    """detection_windows enumerates OpenCV's scan (step 2 up to factor 2, then 1); stump_cost's accepted
    set is cascade_pass's and its cost counts the weak classifiers of every stage a window reaches."""
    rng = np.random.default_rng(5)
    g = rng.integers(0, 256, (48, 64)).astype(np.uint8)
    P = tc.detection_windows(g, 1.2)
    expected, f = 0, 1.0
    while round(tc.WIN_W * f) <= 64 and round(tc.WIN_H * f) <= 48:
        sw, sh = int(round(64 / f)), int(round(48 / f))
        step = 1 if f > 2 else 2
        expected += len(range(0, sh - tc.WIN_H, step)) * len(range(0, sw - tc.WIN_W, step))
        f *= 1.2
    assert P.shape == (expected, tc.WIN_H, tc.WIN_W)
    assert (P[0] == g[:tc.WIN_H, :tc.WIN_W]).all()
    assert len(tc.detection_windows(g, 1.2, 10, rng)) == 10
    rects = tc.enumerate_features()
    stages = _random_cascade(rng, len(rects))
    cost, accepted = tc.stump_cost(stages, rects, P)
    assert (accepted == tc.cascade_pass(stages, tc.compute_features(P))).all()
    assert set(np.unique(cost)) <= {4.0, 8.0, 12.0}
    assert (cost[accepted] == 12).all()
