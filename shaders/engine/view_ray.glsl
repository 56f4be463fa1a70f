#ifndef CUMULO_VIEW_RAY_GLSL
#define CUMULO_VIEW_RAY_GLSL
// The view ray's direction through NDC (x, y) from the inverse view-projection (reversed-Z, finite far plane).
// The point unprojected lies about a kilometre out (NDC depth 1e-4 with a 0.1 m near plane), not at depth 0.5 (0.2 m
// from the camera): there h.xyz / h.w - camera cancels the camera position's leading bits, and at 300 m from the
// origin the direction was off by a few hundredths of a pixel at 320x180, enough that a still camera's reprojection
// (reconstruct.comp, temporal_accumulate.comp) missed its own texel and blurred a settled picture.
// Any NDC depth in (0, 1] lies on the ray in front of the camera.
const float kViewRayNdcDepth = 1e-4;

vec3 view_ray_dir(mat4 inv_view_proj, vec2 ndc, vec3 camera_pos) {
  vec4 h = inv_view_proj * vec4(ndc, kViewRayNdcDepth, 1.0);
  return normalize(h.xyz / h.w - camera_pos);
}
#endif
