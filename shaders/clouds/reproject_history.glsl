// Where a point at `depth` along a pixel's ray (>= 1e5: "at infinity", the rotation alone: a point far enough that
// the camera's translation does not matter) was in the last frame: the uv to fetch a history at, snapped to the
// texel's centre when it lands on one up to float error (a still camera, where bilinear weights of 0.999 / 0.001 would
// blur the history a little more every frame). False: off-screen or behind the camera. Needs the including shader's
// CloudParams `P` (prev_view_proj) and push constant `pc` (target: the history's size and its inverse).
bool reproject(vec3 ro, vec3 rd, float depth, out vec2 fetch_uv, out bool on_texel) {
  vec4 world = depth < 1e5 ? vec4(ro + rd * depth, 1.0) : vec4(rd, 0.0);
  vec4 prev = P.prev_view_proj * world;
  fetch_uv = vec2(0.0);
  on_texel = false;
  if (!(prev.w > 0.0)) return false;
  vec2 prev_uv = prev.xy / prev.w * 0.5 + 0.5;
  if (!(all(greaterThanEqual(prev_uv, vec2(0.0))) && all(lessThanEqual(prev_uv, vec2(1.0))))) return false;
  vec2 prev_px = prev_uv * pc.target.xy - 0.5;
  vec2 snapped = round(prev_px);
  on_texel = all(lessThan(abs(prev_px - snapped), vec2(0.01)));
  fetch_uv = on_texel ? (snapped + 0.5) * pc.target.zw : prev_uv;
  return true;
}
