"""Frames as sensors and PCL write them, before segmentation: depth images with their intrinsics, PCD files of
every DATA kind (organized, or unorganized and put back on the camera's pixels), VCG range maps and Cyberware
range grids; each as an organized grid of camera-frame points with its colours and intrinsics."""
