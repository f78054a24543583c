/* hello_lod.c — acuity's C ABI in a short loop: load a profile, place 20 objects, run 10 frames
 * with a moving gaze, print the levels and the cross-fades in progress (previous level > level
 * @ fade; an engine draws both levels while fade < 1). Usage: hello_lod PROFILE.acuity
 * The scene uses only exactly representable numbers, so any binding given the same inputs must
 * print the same levels (tests/python/test_bindings.py checks the Python API against this). */
#include <stdio.h>
#include <stdlib.h>

#include "acuity.h"

#define OBJECTS 20

static void* read_all(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  void* data;
  long n;
  if (!f) return NULL;
  if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
    fclose(f);
    return NULL;
  }
  data = malloc((size_t)n + 1);
  if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
    free(data);
    data = NULL;
  }
  fclose(f);
  *size = (size_t)n;
  return data;
}

int main(int argc, char** argv) {
  acuity_config config;
  acuity_scheduler* s = NULL;
  acuity_eye eye;
  int32_t profile = -1, profiles[OBJECTS];
  double positions[OBJECTS][3];
  float rotations[OBJECTS][4], scales[OBJECTS], velocities[OBJECTS][3];
  uint32_t ids[OBJECTS];
  uint8_t levels[OBJECTS], previous[OBJECTS];
  float fades[OBJECTS];
  size_t size = 0;
  void* bytes;
  int i, frame;

  if (argc < 2 || !(bytes = read_all(argv[1], &size))) {
    fprintf(stderr, "usage: hello_lod PROFILE.acuity (a readable file)\n");
    return 2;
  }
  acuity_config_default(&config);
  config.max_objects = OBJECTS;
  config.transition_seconds = 0.25f; /* a level change fades in over 16 frames of 1/64 s */
  if (acuity_create(&config, &s) != ACUITY_OK || acuity_load_profile(s, bytes, size, &profile) != ACUITY_OK) {
    fprintf(stderr, "hello_lod: %s\n", acuity_last_error());
    free(bytes);
    acuity_destroy(s);
    return 1;
  }
  free(bytes);
  for (i = 0; i < OBJECTS; ++i) {
    profiles[i] = profile;
    positions[i][0] = (i % 5 - 2) * 3.0;
    positions[i][1] = 0.0;
    positions[i][2] = -(2.0 + i * 4.0);
    rotations[i][0] = rotations[i][1] = rotations[i][2] = 0.0f;
    rotations[i][3] = 1.0f;
    scales[i] = 1.0f;
    velocities[i][0] = i % 3 == 0 ? 2.0f : 0.0f;
    velocities[i][1] = velocities[i][2] = 0.0f;
  }
  if (acuity_add_objects(s, OBJECTS, profiles, &positions[0][0], 0, &rotations[0][0], 0, scales, ids) !=
          ACUITY_OK ||
      acuity_set_velocities(s, OBJECTS, ids, &velocities[0][0], 0) != ACUITY_OK) {
    fprintf(stderr, "hello_lod: %s\n", acuity_last_error());
    acuity_destroy(s);
    return 1;
  }
  acuity_eye_default(&eye);
  eye.gaze_valid = 1;
  for (frame = 0; frame < 10; ++frame) {
    eye.gaze_direction[0] = 0.125f * (float)frame;
    eye.gaze_direction[1] = 0.0f;
    eye.gaze_direction[2] = -1.0f;
    if (acuity_begin_frame(s, &eye, 1, 1.0f / 64.0f) != ACUITY_OK ||
        acuity_update_range(s, 0, 10) != ACUITY_OK || acuity_update_range(s, 10, 10) != ACUITY_OK ||
        acuity_end_frame(s) != ACUITY_OK) {
      fprintf(stderr, "hello_lod: %s\n", acuity_last_error());
      acuity_destroy(s);
      return 1;
    }
  }
  if (acuity_get_levels(s, OBJECTS, ids, levels, NULL) != ACUITY_OK ||
      acuity_get_transitions(s, OBJECTS, ids, previous, fades) != ACUITY_OK) {
    fprintf(stderr, "hello_lod: %s\n", acuity_last_error());
    acuity_destroy(s);
    return 1;
  }
  printf("levels:");
  for (i = 0; i < OBJECTS; ++i) printf(" %u", (unsigned)levels[i]);
  printf("\nfading:");
  for (i = 0; i < OBJECTS; ++i)
    if (fades[i] < 1.0f)
      printf(" %d:%u>%u@%.4f", i, (unsigned)previous[i], (unsigned)levels[i], (double)fades[i]);
  printf("\ntriangles: %llu\n", (unsigned long long)acuity_frame_triangles(s));
  acuity_destroy(s);
  return 0;
}
