/* ncplc IR as C: the helpers every generated program starts with (semantics of compiler::ir). */
#include <stdint.h>
#include <string.h>
#include <math.h>

typedef uint8_t u8;
static inline uint64_t ld(const u8 *m, int at, int n) { uint64_t v = 0; memcpy(&v, m + at, n); return v; }
static inline void st(u8 *m, int at, int n, uint64_t v) { memcpy(m + at, &v, n); }
static inline float ldf(const u8 *m, int at) { float f; memcpy(&f, m + at, 4); return f; }
static inline double ldd(const u8 *m, int at) { double d; memcpy(&d, m + at, 8); return d; }
static inline void stf(u8 *m, int at, float f) { memcpy(m + at, &f, 4); }
static inline void std_(u8 *m, int at, double d) { memcpy(m + at, &d, 8); }
static inline float f32b(uint32_t b) { float f; memcpy(&f, &b, 4); return f; }
static inline double f64b(uint64_t b) { double d; memcpy(&d, &b, 8); return d; }
static inline float c32(float f) { return f != f ? f32b(0x7FC00000u) : f; }
static inline double c64(double d) { return d != d ? f64b(0x7FF8000000000000ull) : d; }
static inline float fmin32(float a, float b) { return b < a ? b : a; }
static inline float fmax32(float a, float b) { return b > a ? b : a; }
static inline double fmin64(double a, double b) { return b < a ? b : a; }
static inline double fmax64(double a, double b) { return b > a ? b : a; }
static inline int64_t sat64(double d) {
  if (d != d) return 0;
  if (d >= 9223372036854775808.0) return INT64_MAX;
  if (d < -9223372036854775808.0) return INT64_MIN;
  return (int64_t)d;
}
static inline int64_t n_bool(int64_t v) { return v != 0; }
static inline int64_t n_byte(int64_t v) { return (uint8_t)v; }
static inline int64_t n_word(int64_t v) { return (uint16_t)v; }
static inline int64_t n_dword(int64_t v) { return (uint32_t)v; }
static inline int64_t n_int(int64_t v) { return (int16_t)v; }
static inline int64_t n_dint(int64_t v) { return (int32_t)v; }
static inline int64_t wadd(int64_t a, int64_t b) { return (int64_t)((uint64_t)a + (uint64_t)b); }
static inline int64_t wsub(int64_t a, int64_t b) { return (int64_t)((uint64_t)a - (uint64_t)b); }
static inline int64_t wmul(int64_t a, int64_t b) { return (int64_t)((uint64_t)a * (uint64_t)b); }
static inline int64_t idiv(u8 *m, int64_t a, int64_t b) {
  if (b == 0) { st(m, FAULTS_AT, 4, ld(m, FAULTS_AT, 4) | 1); return 0; }
  return a / b;
}
static inline int64_t imod(u8 *m, int64_t a, int64_t b) {
  if (b == 0) { st(m, FAULTS_AT, 4, ld(m, FAULTS_AT, 4) | 1); return 0; }
  return a % b;
}
static inline int64_t ishl(int64_t x, int64_t y, uint64_t mask, unsigned bits) {
  uint64_t a = (uint64_t)y & mask;
  return a >= bits ? 0 : (int64_t)((uint64_t)x << a);
}
static inline int64_t ishr(int64_t x, int64_t y, uint64_t mask, unsigned bits) {
  uint64_t a = (uint64_t)y & mask;
  return a >= bits ? (x < 0 ? -1 : 0) : x >> a;
}
static inline int64_t iabs(int64_t x) { return x < 0 ? (int64_t)(0 - (uint64_t)x) : x; }
static inline int64_t imin(int64_t a, int64_t b) { return a < b ? a : b; }
static inline int64_t imax(int64_t a, int64_t b) { return a > b ? a : b; }
static inline uint64_t bcd(uint64_t v, int digits) {
  uint64_t r = 0;
  for (int i = 0; i < digits; i++) { r |= (v % 10) << (4 * i); v /= 10; }
  return r;
}
static inline uint64_t bin(uint64_t v, int digits) {
  uint64_t r = 0, scale = 1;
  for (int i = 0; i < digits; i++) { r += ((v >> (4 * i)) & 0xF) * scale; scale *= 10; }
  return r;
}
static inline int32_t et_add(int32_t et, int32_t tick) { return (int32_t)((uint32_t)et + (uint32_t)tick); }
static inline void ton(u8 *m, int at, int32_t pt, int32_t tick, int x) {
  int prev = (m[at + 4] & 2) != 0;
  int32_t et = (int32_t)ld(m, at, 4);
  if (x && prev) { et = et_add(et, tick); if (et > pt) et = pt; } else et = 0;
  int q = x && et >= pt;
  st(m, at, 4, (uint32_t)et);
  m[at + 4] = (u8)(q | (x ? 2 : 0));
}
static inline void tof(u8 *m, int at, int32_t pt, int32_t tick, int x) {
  u8 f = m[at + 4];
  int prev = (f & 2) != 0, running = (f & 4) != 0, run = 0;
  int32_t et = (int32_t)ld(m, at, 4);
  if (x) et = 0;
  else {
    if (prev) { run = 1; et = 0; }
    else if (running) { run = 1; et = et_add(et, tick); }
    if (run && et >= pt) run = 0;
  }
  st(m, at, 4, (uint32_t)et);
  m[at + 4] = (u8)((x || run) | (x ? 2 : 0) | (run ? 4 : 0));
}
static inline void tp(u8 *m, int at, int32_t pt, int32_t tick, int x) {
  u8 f = m[at + 4];
  int prev = (f & 2) != 0, running = (f & 4) != 0, run;
  int32_t et = (int32_t)ld(m, at, 4);
  if (running) { et = et_add(et, tick); run = et < pt; }
  else if (x && !prev && pt > 0) { et = 0; run = 1; }
  else { if (!x) et = 0; run = 0; }
  st(m, at, 4, (uint32_t)et);
  m[at + 4] = (u8)(run | (x ? 2 : 0) | (run ? 4 : 0));
}
static inline void pulse(u8 *m, int at, int x) {
  int prev = (m[at] & 2) != 0;
  m[at] = (u8)((x && !prev) | (x ? 2 : 0));
}
static inline void count(u8 *m, int at, int up, int x) {
  u8 f = m[at + 4];
  if (x && !(f & 2) && !(f & 4)) {
    int32_t cv = (int32_t)ld(m, at, 4);
    if (up) { if (cv != INT32_MAX) cv++; } else { if (cv != INT32_MIN) cv--; }
    st(m, at, 4, (uint32_t)cv);
  }
  m[at + 4] = (u8)((f & ~2) | (x ? 2 : 0));
}
static inline void creset(u8 *m, int at, int32_t cv0, int x) {
  if (x) st(m, at, 4, (uint32_t)cv0);
  u8 f = m[at + 4];
  m[at + 4] = (u8)((f & ~4) | (x ? 4 : 0));
}
