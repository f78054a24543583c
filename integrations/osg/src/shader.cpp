// The cross-fade shader: a headlight-lit colour, and the screen-door (ordered dither) blend between
// the level faded in and the one faded out. The two draw complementary pixel sets: the incoming
// level where threshold(x, y) < fade, the outgoing one elsewhere, so the sum is one full surface.
#include <osg/Program>
#include <osg/Shader>
#include <osg/Uniform>

#include "acuity/osg/kit.hpp"

namespace acuity::osg {
namespace {

const char* kVertex = R"(#version 120
varying vec3 acuity_eye_position;
void main() {
  acuity_eye_position = (gl_ModelViewMatrix * gl_Vertex).xyz;
  gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;
}
)";

const char* kFragment = R"(#version 120
uniform vec4 acuity_color;        // the material's base colour
uniform vec4 acuity_level_color;  // the debug palette's colour for the drawn level
uniform float acuity_debug;       // 0: material, 1: colour by level
uniform float acuity_fade;        // weight of the incoming level, 0..1 (1: not fading)
uniform bool acuity_outgoing;     // this draw is the level faded out
varying vec3 acuity_eye_position;

// 8x8 Bayer threshold in [0, 1) by bit interleaving (x ^ y, x) reversed.
float acuity_dither(vec2 p) {
  vec2 q = mod(floor(p), 8.0);
  float x = q.x, y = q.y, v = 0.0, w = 32.0;
  for (int i = 0; i < 3; ++i) {
    float xb = mod(x, 2.0), yb = mod(y, 2.0);
    v += w * abs(xb - yb) + 0.5 * w * yb;
    x = floor(x / 2.0); y = floor(y / 2.0); w /= 4.0;
  }
  return v / 64.0;
}

void main() {
  float t = acuity_dither(gl_FragCoord.xy);
  if (acuity_outgoing ? t < acuity_fade : t >= acuity_fade) discard;
  vec3 n = normalize(cross(dFdx(acuity_eye_position), dFdy(acuity_eye_position)));
  float light = 0.25 + 0.75 * abs(n.z);
  vec4 c = mix(acuity_color, acuity_level_color, acuity_debug);
  gl_FragColor = vec4(c.rgb * light, 1.0);
}
)";

}  // namespace

float dither_threshold(int x, int y) {  // the shader's acuity_dither, on the CPU
  int v = 0, w = 32;
  x &= 7;
  y &= 7;
  for (int i = 0; i < 3; ++i) {
    const int xb = x & 1, yb = y & 1;
    v += w * (xb ^ yb) + (w / 2) * yb;
    x >>= 1;
    y >>= 1;
    w /= 4;
  }
  return float(v) / 64.0f;
}

::osg::Vec4 level_color(std::uint32_t level) {
  static const ::osg::Vec4 palette[] = {
      {0.15f, 0.35f, 1.0f, 1}, {0.0f, 0.85f, 0.9f, 1}, {0.2f, 0.85f, 0.2f, 1}, {0.95f, 0.9f, 0.1f, 1},
      {1.0f, 0.55f, 0.1f, 1},  {0.9f, 0.15f, 0.1f, 1}, {0.6f, 0.2f, 0.8f, 1}};
  return level < 7 ? palette[level] : ::osg::Vec4(0.6f, 0.6f, 0.6f, 1);
}

::osg::ref_ptr<::osg::StateSet> make_shader_state() {
  ::osg::ref_ptr<::osg::StateSet> ss = new ::osg::StateSet;
  ::osg::ref_ptr<::osg::Program> program = new ::osg::Program;
  program->setName("acuity_crossfade");
  program->addShader(new ::osg::Shader(::osg::Shader::VERTEX, kVertex));
  program->addShader(new ::osg::Shader(::osg::Shader::FRAGMENT, kFragment));
  ss->setAttributeAndModes(program.get(), ::osg::StateAttribute::ON);
  ss->addUniform(new ::osg::Uniform("acuity_color", ::osg::Vec4(0.8f, 0.8f, 0.8f, 1)));
  ss->addUniform(new ::osg::Uniform("acuity_level_color", level_color(0)));
  ss->addUniform(new ::osg::Uniform("acuity_debug", 0.0f));
  ss->addUniform(new ::osg::Uniform("acuity_fade", 1.0f));
  ss->addUniform(new ::osg::Uniform("acuity_outgoing", false));
  return ss;
}

}  // namespace acuity::osg
