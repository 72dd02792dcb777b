// The pinhole camera of SceneInfo: raster position <-> world direction.
// Raster (px, py) in [0, width) x [0, height), y down (shared/scene_types.h SceneInfo).
#ifndef PMCR_CAMERA_GLSL
#define PMCR_CAMERA_GLSL

#include "common/scene.glsl"

// Unnormalised direction through raster position p (the image plane at distance 1).
vec3 cameraDirectionUnnormalized(vec2 p) {
    float sx = (2.0 * p.x / float(sceneInfo.width) - 1.0) * sceneInfo.tanHalfFovY * sceneInfo.aspect;
    float sy = (1.0 - 2.0 * p.y / float(sceneInfo.height)) * sceneInfo.tanHalfFovY;
    return sceneInfo.cameraForward + sx * sceneInfo.cameraRight + sy * sceneInfo.cameraUp;
}
vec3 cameraDirection(vec2 p) { return normalize(cameraDirectionUnnormalized(p)); }

// Inverse of cameraDirection: the raster position a direction from the pinhole passes
// through; false when it points behind the camera or leaves the image.
bool cameraRasterPosition(vec3 dir, out vec2 p) {
    float z = dot(dir, sceneInfo.cameraForward);
    if (z <= 0.0) return false;
    float sx = dot(dir, sceneInfo.cameraRight) / z;
    float sy = dot(dir, sceneInfo.cameraUp) / z;
    p.x = (sx / (sceneInfo.tanHalfFovY * sceneInfo.aspect) + 1.0) * 0.5 * float(sceneInfo.width);
    p.y = (1.0 - sy / sceneInfo.tanHalfFovY) * 0.5 * float(sceneInfo.height);
    return p.x >= 0.0 && p.y >= 0.0 && p.x < float(sceneInfo.width) && p.y < float(sceneInfo.height);
}

// Area of one pixel on the image plane at distance 1 (the raster -> image-plane Jacobian).
float cameraPixelArea() {
    float w = 2.0 * sceneInfo.tanHalfFovY * sceneInfo.aspect / float(sceneInfo.width);
    float h = 2.0 * sceneInfo.tanHalfFovY / float(sceneInfo.height);
    return w * h;
}

#endif
