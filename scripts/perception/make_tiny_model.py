"""Writes tests/data/perception/tiny-maskrcnn.onnx (and its class description, tiny-maskrcnn.json): a few-hundred-byte stand-in for the Mask R-CNN
export with the same contract (input `images_tensors` f32 [3,H,W]; outputs `boxes` f32 [N,4],
`labels` i64 [N], `scores` f32 [N], `masks` f32 [N,1,28,28]), so the Rust session code is tested
without torch or the real model.

Two detections: a cube at [10,20,38,48] with a disc mask and score sigmoid(4*mean(image)-2)
(0.8808 on a white image, 0.1192 on a black one), and a rope at [100,50,200,60] with a full mask
and score 0.3. Deterministic; needs only the `onnx` and `numpy` packages.

    python scripts/perception/make_tiny_model.py tests/data/perception/tiny-maskrcnn.onnx
"""

import json
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

from common import CLASSES


def main(path: str) -> None:
    yy, xx = np.mgrid[0:28, 0:28]
    disc = (((yy - 13.5) ** 2 + (xx - 13.5) ** 2) <= 10.0**2).astype(np.float32)
    masks = np.stack([disc, np.ones((28, 28), np.float32)])[:, None, :, :]
    constants = [
        numpy_helper.from_array(np.array([[10, 20, 38, 48], [100, 50, 200, 60]], np.float32), "boxes_c"),
        numpy_helper.from_array(np.array([1, 3], np.int64), "labels_c"),
        numpy_helper.from_array(masks.astype(np.float32), "masks_c"),
        numpy_helper.from_array(np.array(4.0, np.float32), "gain"),
        numpy_helper.from_array(np.array(2.0, np.float32), "offset"),
        numpy_helper.from_array(np.array([1], np.int64), "one_shape"),
        numpy_helper.from_array(np.array([0.3], np.float32), "second_score"),
    ]
    nodes = [
        helper.make_node("ReduceMean", ["images_tensors"], ["mean"], keepdims=0),
        helper.make_node("Mul", ["mean", "gain"], ["scaled"]),
        helper.make_node("Sub", ["scaled", "offset"], ["logit"]),
        helper.make_node("Sigmoid", ["logit"], ["first_score"]),
        helper.make_node("Reshape", ["first_score", "one_shape"], ["first_score_1"]),
        helper.make_node("Concat", ["first_score_1", "second_score"], ["scores"], axis=0),
        helper.make_node("Identity", ["boxes_c"], ["boxes"]),
        helper.make_node("Identity", ["labels_c"], ["labels"]),
        helper.make_node("Identity", ["masks_c"], ["masks"]),
    ]
    graph = helper.make_graph(
        nodes,
        "tiny_maskrcnn",
        [helper.make_tensor_value_info("images_tensors", TensorProto.FLOAT, [3, "H", "W"])],
        [
            helper.make_tensor_value_info("boxes", TensorProto.FLOAT, ["N", 4]),
            helper.make_tensor_value_info("labels", TensorProto.INT64, ["N"]),
            helper.make_tensor_value_info("scores", TensorProto.FLOAT, ["N"]),
            helper.make_tensor_value_info("masks", TensorProto.FLOAT, ["N", 1, 28, 28]),
        ],
        initializer=constants,
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], producer_name="contphy-eval")
    model.ir_version = 8
    onnx.checker.check_model(model)
    onnx.save(model, path)
    # The description beside the model names its classes (the Rust side reads labels from it).
    description = os.path.splitext(path)[0] + ".json"
    with open(description, "w") as out:
        json.dump({"model": os.path.basename(path), "classes": {str(k): v for k, v in CLASSES.items()}}, out, indent=1)
        out.write("\n")


if __name__ == "__main__":
    main(sys.argv[1])
