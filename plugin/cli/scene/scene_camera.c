/* Scene "camera": the view of rendered frames. */
#include <math.h>
#include <string.h>

#include "scene_parts.h"

int scene_parse_camera(const sj_ctx* c, const cJSON* root, scene* s) {
    scene_camera* cam = &s->camera;
    memset(cam, 0, sizeof *cam);
    cam->up[1] = 1.0;
    cam->fov_deg = SCENE_DEFAULT_FOV_DEG;
    cam->width = SCENE_DEFAULT_WIDTH;
    cam->height = SCENE_DEFAULT_HEIGHT;
    const cJSON* obj = NULL;
    int r = sj_object(c, root, "", "camera", &obj);
    if (r <= 0) return r;
    static const char* const keys[] = {"eye", "target", "up", "fov_deg", "width", "height"};
    if (sj_check_object(c, obj, "camera", keys, COUNT(keys)) < 0) return -1;
    const int has_eye = sj_get(obj, "eye") != NULL, has_target = sj_get(obj, "target") != NULL;
    if (has_eye != has_target)
        return sj_fail(c, has_eye ? "camera.target" : "camera.eye",
                       "missing (give both \"eye\" and \"target\", or neither for automatic framing)");
    if (sj_numbers(c, obj, "camera", "eye", 3, cam->eye) < 0) return -1;
    if (sj_numbers(c, obj, "camera", "target", 3, cam->target) < 0) return -1;
    if (sj_unit_vector(c, obj, "camera", "up", cam->up) < 0) return -1;
    if (sj_number(c, obj, "camera", "fov_deg", SJ_POSITIVE, &cam->fov_deg) < 0) return -1;
    if (!(cam->fov_deg < 180)) return sj_fail(c, "camera.fov_deg", "must be in (0, 180), not %g", cam->fov_deg);
    if (sj_int(c, obj, "camera", "width", 1, SCENE_MAX_IMAGE_SIDE, &cam->width) < 0) return -1;
    if (sj_int(c, obj, "camera", "height", 1, SCENE_MAX_IMAGE_SIDE, &cam->height) < 0) return -1;
    if (has_eye) {
        double d[3], len = 0;
        for (int k = 0; k < 3; ++k) {
            d[k] = cam->target[k] - cam->eye[k];
            len += d[k] * d[k];
        }
        len = sqrt(len);
        if (!(len > 0) || !isfinite(len)) return sj_fail(c, "camera.target", "must differ from camera.eye");
        const double along = (d[0] * cam->up[0] + d[1] * cam->up[1] + d[2] * cam->up[2]) / len;
        if (fabs(along) > 0.999999)
            return sj_fail(c, "camera.up", "must not be parallel to the view direction (target - eye)");
        cam->framed = 1;
    }
    return 0;
}
