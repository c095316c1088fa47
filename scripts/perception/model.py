"""The Mask R-CNN used by contphy-eval: torchvision MaskRCNN, mobilenet_v3_small + FPN (trained from
scratch, BatchNorm2d), 480x270 processed natively (no resize), slim heads."""
from collections import OrderedDict

import torch
from torch import nn
from torchvision.models import mobilenet_v3_small
from torchvision.models.detection import MaskRCNN
from torchvision.models.detection.anchor_utils import AnchorGenerator
from torchvision.models.detection.backbone_utils import BackboneWithFPN
from torchvision.models.detection.faster_rcnn import FastRCNNPredictor, TwoMLPHead
from torchvision.models.detection.mask_rcnn import MaskRCNNHeads, MaskRCNNPredictor
from torchvision.models.detection.transform import GeneralizedRCNNTransform
from torchvision.ops import MultiScaleRoIAlign
from torchvision.ops.feature_pyramid_network import LastLevelMaxPool

from common import NUM_CLASSES

def model_config(num_classes=NUM_CLASSES):
    """The architecture description (checkpoint metadata, the model's .json) for `num_classes`
    classes including background (rope 9, fluid 5, ball 5, cloth 4)."""
    return {
        "backbone": "mobilenet_v3_small features (BatchNorm2d, from scratch), FPN on strides 8/16/32 + maxpool 64",
        "return_layers": {"3": "0", "8": "1", "12": "2"},
        "fpn_out_channels": 128,
        "anchor_sizes": [[16], [32], [64], [128]],
        "aspect_ratios": [0.25, 0.5, 1.0, 2.0, 4.0],
        "box_head": f"TwoMLPHead(128*7*7 -> 256 -> 256), FastRCNNPredictor(256, {num_classes})",
        "mask_head": f"MaskRCNNHeads(128, [64,64,64,64]), MaskRCNNPredictor(64, 64, {num_classes}), 28x28 masks",
        "roi_align": "box 7x7 sampling 2, mask 14x14 sampling 2, levels 0,1,2",
        "normalization": "in graph: (x - [0.485,0.456,0.406]) / [0.229,0.224,0.225]; no resize; pad to /32",
    }


CONFIG = model_config(NUM_CLASSES)  # rope


class NoResizeTransform(GeneralizedRCNNTransform):
    """Normalizes and batches, but keeps the input resolution."""

    def __init__(self, paste_masks=True):
        super().__init__(min_size=270, max_size=480, image_mean=[0.485, 0.456, 0.406],
                         image_std=[0.229, 0.224, 0.225])
        self.paste_masks = paste_masks

    def resize(self, image, target=None):
        return image, target

    def postprocess(self, result, image_shapes, original_image_sizes):
        if self.training or self.paste_masks:
            return super().postprocess(result, image_shapes, original_image_sizes)
        return result  # raw [N,1,28,28] mask probabilities of each detection's own class; boxes in input pixels


def build_model(paste_masks=True, score_thresh=0.05, nms_thresh=0.5, detections=100, num_classes=NUM_CLASSES):
    feats = mobilenet_v3_small(weights=None, norm_layer=nn.BatchNorm2d).features
    c = CONFIG["fpn_out_channels"]
    backbone = BackboneWithFPN(feats, return_layers=CONFIG["return_layers"], in_channels_list=[24, 48, 576],
                               out_channels=c, extra_blocks=LastLevelMaxPool())
    anchors = AnchorGenerator(tuple(tuple(s) for s in CONFIG["anchor_sizes"]),
                              (tuple(CONFIG["aspect_ratios"]),) * len(CONFIG["anchor_sizes"]))
    box_pool = MultiScaleRoIAlign(["0", "1", "2"], 7, 2)
    mask_pool = MultiScaleRoIAlign(["0", "1", "2"], 14, 2)
    model = MaskRCNN(
        backbone, num_classes=None,
        rpn_anchor_generator=anchors,
        box_roi_pool=box_pool,
        box_head=TwoMLPHead(c * 49, 256),
        box_predictor=FastRCNNPredictor(256, num_classes),
        mask_roi_pool=mask_pool,
        mask_head=MaskRCNNHeads(c, [64, 64, 64, 64], 1),
        mask_predictor=MaskRCNNPredictor(64, 64, num_classes),
        rpn_pre_nms_top_n_train=1000, rpn_post_nms_top_n_train=500,
        rpn_pre_nms_top_n_test=500, rpn_post_nms_top_n_test=200,
        rpn_batch_size_per_image=128,
        box_batch_size_per_image=64,
        box_score_thresh=score_thresh, box_nms_thresh=nms_thresh, box_detections_per_img=detections,
    )
    model.transform = NoResizeTransform(paste_masks=paste_masks)
    return model
