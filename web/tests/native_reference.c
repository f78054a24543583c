/* native_reference SCENE.txt — runs a recorded scene through the native C ABI (acuity::c) and prints
 * every frame's levels and flags, for the web tests to compare with the WebAssembly module bit for
 * bit. It fills acuity_config and acuity_eye field by field itself (not through web/acuity_web.c), so
 * the shim is checked too. The scene is text, tokens separated by white space:
 *
 *   acuity-scene 1
 *   config NAME VALUE                       any number; acuity_config field names
 *   profile FILE                            a file name in the scene's folder (no '/')
 *   objects N   then N x: PROFILE PX PY PZ QX QY QZ QW SCALE
 *   cut CLUSTERS GROUPS PROFILE BUDGET      optional: one object drawn as a cluster cut; file names in
 *                                           the scene's folder: the hierarchy's records as
 *                                           ACUITY_cluster_hierarchy stores them (16 bytes per
 *                                           cluster, 32 per group) and its profile; BUDGET triangles
 *                                           (0: none, acuity_select_cut_budget)
 *   frames M    then M x: frame DT EYES MOVES
 *                           EYES x:  eye + 28 numbers (the layout of web/acuity_web.c)
 *                           MOVES x: move INDEX PX PY PZ QX QY QZ QW SCALE
 *                           with a cut: cut PX PY PZ QX QY QZ QW SCALE (its transform that frame)
 *   end
 *
 * Output, per frame k: "frame k triangles T", "levels L...", "flags F...", and with a cut (selected
 * after the frame's acuity_end_frame) "cut S F T H C B ids...": its status, flags, triangles, held,
 * budget_coarsened, budget_forced and drawn cluster ids.
 * Options: --repeat R runs the frames R times and prints only the time per frame (for bench.mjs).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "acuity.h"

static FILE* in;
static const char* scene_path;

static void die(const char* what) {
  fprintf(stderr, "native_reference: %s: %s\n", scene_path, what);
  exit(1);
}

static void check(acuity_status st, const char* call) {
  if (st != ACUITY_OK) {
    fprintf(stderr, "native_reference: %s failed (%d): %s\n", call, (int)st, acuity_last_error());
    exit(1);
  }
}

static const char* word(void) {
  static char buf[4096];
  if (fscanf(in, "%4095s", buf) != 1) die("unexpected end of scene");
  return buf;
}

static void expect(const char* w) {
  if (strcmp(word(), w) != 0) {
    fprintf(stderr, "native_reference: expected '%s'\n", w);
    die("bad scene");
  }
}

static double number(void) {
  const char* w = word();
  char* end = NULL;
  const double v = strtod(w, &end);
  if (end == w || *end) die("bad number");
  return v;
}

static unsigned long count(unsigned long max) {
  const double v = number();
  if (!(v >= 0 && v <= (double)max) || v != (double)(unsigned long)v) die("bad count");
  return (unsigned long)v;
}

static void set_config(acuity_config* c, const char* name, double v) {
  if (!strcmp(name, "max_objects"))
    c->max_objects = (uint32_t)v;
  else if (!strcmp(name, "max_profiles"))
    c->max_profiles = (uint32_t)v;
  else if (!strcmp(name, "rule"))
    c->rule = (uint32_t)v;
  else if (!strcmp(name, "evaluation"))
    c->evaluation = (uint32_t)v;
  else if (!strcmp(name, "quality"))
    c->quality = (float)v;
  else if (!strcmp(name, "gaze_uncertainty_deg"))
    c->gaze_uncertainty_deg = (float)v;
  else if (!strcmp(name, "no_gaze_radius_deg"))
    c->no_gaze_radius_deg = (float)v;
  else if (!strcmp(name, "hysteresis_margin"))
    c->hysteresis_margin = (float)v;
  else if (!strcmp(name, "hysteresis_frames"))
    c->hysteresis_frames = (uint32_t)v;
  else if (!strcmp(name, "saccade_speed_deg_s"))
    c->saccade_speed_deg_s = (float)v;
  else if (!strcmp(name, "triangle_budget"))
    c->triangle_budget = (uint64_t)v;
  else
    die("unknown config field");
}

static unsigned char* read_file(const char* name, size_t* size) {
  if (strchr(name, '/') || !strcmp(name, "..") || !strcmp(name, "."))
    die("a profile or hierarchy must be a file name in the scene's folder");
  const char* slash = strrchr(scene_path, '/');
  const size_t dir = slash ? (size_t)(slash - scene_path + 1) : 0;
  char* path = malloc(dir + strlen(name) + 1);
  if (!path) die("out of memory");
  memcpy(path, scene_path, dir);
  strcpy(path + dir, name);
  FILE* f = fopen(path, "rb");
  if (!f) die("cannot open a profile or hierarchy");
  unsigned char* bytes = NULL;
  size_t n = 0, cap = 0;
  for (;;) {
    if (n == cap) {
      cap = cap ? 2 * cap : 65536;
      if (cap > ((size_t)1 << 30)) die("profile or hierarchy too large");
      unsigned char* grown = realloc(bytes, cap);
      if (!grown) die("out of memory");
      bytes = grown;
    }
    const size_t got = fread(bytes + n, 1, cap - n, f);
    n += got;
    if (got == 0) break;
  }
  fclose(f);
  free(path);
  *size = n;
  return bytes;
}

typedef struct Frame {
  float dt;
  uint32_t eye_count, move_count;
  acuity_eye eyes[2];
  double cut_position[3];
  float cut_rotation[4], cut_scale;
  uint32_t* move_index;
  double* move_position;
  float *move_rotation, *move_scale;
} Frame;

static void read_floats(float* out, int n) {
  for (int k = 0; k < n; ++k) out[k] = (float)number();
}

static void read_eye(acuity_eye* e) {
  acuity_eye_default(e);
  for (int k = 0; k < 3; ++k) e->position[k] = number();
  read_floats(e->orientation, 4);
  read_floats(e->fov_deg, 4);
  for (int k = 0; k < 2; ++k) e->viewport[k] = (uint32_t)count(1000000000ul);
  read_floats(e->velocity, 3);
  read_floats(e->angular_velocity, 3);
  read_floats(e->gaze_direction, 3);
  e->gaze_confidence = (float)number();
  read_floats(e->gaze_angular_velocity, 3);
  e->gaze_valid = number() != 0;
  e->gaze_has_velocity = number() != 0;
}

static void read_transform(double* p, float* q, float* s) {
  for (int k = 0; k < 3; ++k) p[k] = number();
  read_floats(q, 4);
  *s = (float)number();
}

int main(int argc, char** argv) {
  long repeat = 0;
  if (argc == 4 && !strcmp(argv[2], "--repeat"))
    repeat = atol(argv[3]);
  else if (argc != 2) {
    fprintf(stderr, "usage: native_reference SCENE.txt [--repeat R]\n");
    return 2;
  }
  scene_path = argv[1];
  in = fopen(scene_path, "r");
  if (!in) die("cannot open");
  expect("acuity-scene");
  if (number() != 1) die("version 1 expected");

  acuity_config config;
  acuity_config_default(&config);
  const char* w;
  char name[256];
  while (!strcmp(w = word(), "config")) {
    const char* key = word();
    if (strlen(key) >= sizeof name) die("config field name too long");
    memcpy(name, key, strlen(key) + 1);
    set_config(&config, name, number());
  }
  acuity_scheduler* s = NULL;
  check(acuity_create(&config, &s), "acuity_create");
  while (!strcmp(w, "profile")) {
    size_t size = 0;
    unsigned char* bytes = read_file(word(), &size);
    int32_t index = -1;
    check(acuity_load_profile(s, bytes, size, &index), "acuity_load_profile");
    free(bytes);
    w = word();
  }
  if (strcmp(w, "objects")) die("expected 'objects'");
  const uint32_t n = (uint32_t)count(10000000ul);
  int32_t* profiles = malloc(n * sizeof *profiles + 1);
  double* positions = malloc(3 * n * sizeof *positions + 1);
  float* rotations = malloc(4 * n * sizeof *rotations + 1);
  float* scales = malloc(n * sizeof *scales + 1);
  uint32_t* ids = malloc(n * sizeof *ids + 1);
  uint8_t* levels = malloc(n + 1);
  uint8_t* flags = malloc(n + 1);
  if (!profiles || !positions || !rotations || !scales || !ids || !levels || !flags) die("out of memory");
  for (uint32_t i = 0; i < n; ++i) {
    profiles[i] = (int32_t)count(1000000ul);
    read_transform(positions + 3 * i, rotations + 4 * i, scales + i);
  }
  check(acuity_add_objects(s, n, profiles, positions, 0, rotations, 0, scales, ids), "acuity_add_objects");

  acuity_hierarchy* h = NULL;
  uint64_t cut_budget = 0;
  uint32_t cluster_count = 0;
  void* cut_memory = NULL;
  uint32_t* cut_drawn = NULL;
  w = word();
  if (!strcmp(w, "cut")) {
    size_t cluster_bytes = 0, group_bytes = 0, profile_bytes = 0;
    unsigned char* clusters = read_file(word(), &cluster_bytes);
    unsigned char* groups = read_file(word(), &group_bytes);
    unsigned char* profile = read_file(word(), &profile_bytes);
    cut_budget = (uint64_t)count(9007199254740992ul);
    if (cluster_bytes % sizeof(acuity_cluster) || group_bytes % sizeof(acuity_cluster_group))
      die("hierarchy records of a size that is not whole records");
    cluster_count = (uint32_t)(cluster_bytes / sizeof(acuity_cluster));
    check(acuity_hierarchy_create_from_profile(
              (const acuity_cluster*)clusters, cluster_count, (const acuity_cluster_group*)groups,
              (uint32_t)(group_bytes / sizeof(acuity_cluster_group)), profile, profile_bytes, &h),
          "acuity_hierarchy_create_from_profile");
    free(clusters);
    free(groups);
    free(profile);
    cut_memory = calloc(acuity_cut_memory_size(h) / 4 + 1, 4); /* zeroed, 4-byte aligned */
    cut_drawn = malloc(cluster_count * sizeof *cut_drawn + 1);
    if (!cut_memory || !cut_drawn) die("out of memory");
    w = word();
  }
  if (strcmp(w, "frames")) die("expected 'frames'");
  const uint32_t m = (uint32_t)count(1000000ul);
  Frame* frames = calloc(m + 1, sizeof *frames);
  if (!frames) die("out of memory");
  for (uint32_t f = 0; f < m; ++f) {
    Frame* fr = &frames[f];
    expect("frame");
    fr->dt = (float)number();
    fr->eye_count = (uint32_t)count(2);
    fr->move_count = (uint32_t)count(n);
    for (uint32_t e = 0; e < fr->eye_count; ++e) {
      expect("eye");
      read_eye(&fr->eyes[e]);
    }
    fr->move_index = malloc(fr->move_count * sizeof(uint32_t) + 1);
    fr->move_position = malloc(3 * fr->move_count * sizeof(double) + 1);
    fr->move_rotation = malloc(4 * fr->move_count * sizeof(float) + 1);
    fr->move_scale = malloc(fr->move_count * sizeof(float) + 1);
    if (!fr->move_index || !fr->move_position || !fr->move_rotation || !fr->move_scale) die("out of memory");
    for (uint32_t k = 0; k < fr->move_count; ++k) {
      expect("move");
      const uint32_t i = (uint32_t)count(n - 1);
      fr->move_index[k] = ids[i];
      read_transform(fr->move_position + 3 * k, fr->move_rotation + 4 * k, fr->move_scale + k);
    }
    if (h) {
      expect("cut");
      read_transform(fr->cut_position, fr->cut_rotation, &fr->cut_scale);
    }
  }
  expect("end");
  fclose(in);

  const long rounds = repeat > 0 ? repeat : 1;
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  for (long r = 0; r < rounds; ++r)
    for (uint32_t f = 0; f < m; ++f) {
      const Frame* fr = &frames[f];
      if (fr->move_count)
        check(acuity_set_transforms(s, fr->move_count, fr->move_index, fr->move_position, 0,
                                    fr->move_rotation, 0, fr->move_scale),
              "acuity_set_transforms");
      check(acuity_begin_frame(s, fr->eyes, fr->eye_count, fr->dt), "acuity_begin_frame");
      check(acuity_update_range(s, 0, n), "acuity_update_range");
      check(acuity_end_frame(s), "acuity_end_frame");
      check(acuity_get_levels(s, n, ids, levels, flags), "acuity_get_levels");
      if (repeat > 0) continue;
      printf("frame %u triangles %llu\nlevels", f, (unsigned long long)acuity_frame_triangles(s));
      for (uint32_t i = 0; i < n; ++i) printf(" %u", levels[i]);
      printf("\nflags");
      for (uint32_t i = 0; i < n; ++i) printf(" %u", flags[i]);
      printf("\n");
      if (!h) continue;
      acuity_cut_result r;
      memset(&r, 0, sizeof r);
      r.struct_size = sizeof r;
      check(
          acuity_select_cut_budget(s, h, fr->cut_position, fr->cut_rotation, fr->cut_scale, NULL, cut_budget,
                                   cut_memory, acuity_cut_memory_size(h), cluster_count, cut_drawn, &r),
          "acuity_select_cut_budget");
      printf("cut %u %u %llu %u %u %u", r.status, r.flags, (unsigned long long)r.triangles, r.held,
             r.budget_coarsened, r.budget_forced);
      for (uint32_t c = 0; c < r.clusters; ++c) printf(" %u", cut_drawn[c]);
      printf("\n");
    }
  clock_gettime(CLOCK_MONOTONIC, &t1);
  if (repeat > 0)
    printf("{\"frames\": %ld, \"objects\": %u, \"seconds_per_frame\": %.9g}\n", rounds * (long)m, n,
           ((double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec)) /
               (double)(rounds * (long)m));
  acuity_hierarchy_destroy(h);
  free(cut_memory);
  free(cut_drawn);
  acuity_destroy(s);
  return 0;
}
