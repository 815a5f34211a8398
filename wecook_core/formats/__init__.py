"""Importers and exporters, one module per outside format.

Why wecook reads these formats itself (looked at December 2026): labelformat reads image detection formats
(COCO, YOLO, Pascal VOC, KITTI, Labelbox), none of the video track formats here; supervision's
``DetectionDataset`` reads COCO, YOLO and Pascal VOC images, no tracks; pycocotools indexes COCO image JSON
(no ``videos``, ``frame_index`` or YouTube-VIS ``bboxes`` lists) and asserts on bad input; datumaro reads
CVAT and MOT, but its MOT reader takes commas only (not PathTrack's spaces) in a ``gt/gt.txt`` folder
layout, reads neither Label Studio video, COCO-VID/TAO/YouTube-VIS nor OpenPose, fails with assertions
rather than a file and a line, and brings a large dependency tree. What wecook needs of an importer is the
tool's meaning (CVAT's interpolation and ``outside``, Label Studio's 1-based frames at its own frame rate,
MOT's 1-based frames) and errors in the file's own terms (its line, its frame numbering, its track id):
none of these libraries gives that, and each format here is a few hundred lines of the standard library.
"""
