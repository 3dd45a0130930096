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
