#version 450
// The Envelope method's density (envelope_density.glsl, with the near detail) at a list of world points: EnvelopeLayer's
// probe, for tests (the profile against the talk's formula, the yield) and debugging.
#extension GL_GOOGLE_include_directive : require
#include "clouds/envelope_density.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = ENV_BINDING_PROBE_POINTS, std430) readonly buffer Points { vec4 points[]; };
layout(set = 0, binding = ENV_BINDING_PROBE_OUT, std430) writeonly buffer Samples { vec4 samples[]; };
layout(push_constant) uniform Push { uvec4 count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count.x) return;
  EnvelopeSample s = envelope_sample(points[i].xyz, true);
  samples[i] = vec4(s.density, s.profile, s.hf, s.edge);
}
