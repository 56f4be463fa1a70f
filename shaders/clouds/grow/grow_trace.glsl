// The backtrace of the cloud-formation solver's advection (solver.cpp's vel and trace): the flow before the step
// plus the ambient wind shear, in cells per step, traced with the midpoint rule. Include after declaring the old
// face velocities as fields u_old, v_old, w_old.
#ifndef CUMULO_GROW_TRACE_GLSL
#define CUMULO_GROW_TRACE_GLSL

GROW_TRILINEAR(grow_sample_u, u_old)
GROW_TRILINEAR(grow_sample_v, v_old)
GROW_TRILINEAR(grow_sample_w, w_old)

vec3 grow_velocity(vec3 p) {
  ivec3 n = P.dims.xyz;
  vec3 r = vec3(grow_sample_u(n + ivec3(1, 0, 0), p - vec3(0.0, 0.5, 0.5)),
                grow_sample_v(n + ivec3(0, 1, 0), p - vec3(0.5, 0.0, 0.5)),
                grow_sample_w(n + ivec3(0, 0, 1), p - vec3(0.5, 0.5, 0.0)));
  float h = clamp(p.y, 0.0, float(n.y)) - P.grid.w;
  r.x += P.shear.x * h;
  r.z += P.shear.y * h;
  return r * P.grid.z;
}

vec3 grow_trace(vec3 p, float dir) {
  vec3 mid = p + 0.5 * dir * grow_velocity(p);
  return p + dir * grow_velocity(mid);
}

#endif
