#pragma once
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>
#include "codec/logistic_mixing.h"
#include "codec/spiht4d_common.h"
namespace fvv {
namespace prior_exp {
inline thread_local int g_channel = 0;
inline void InitProbs(std::vector<mixing::CountedProb>* probs) {
  const char* f = std::getenv("FVV_PRIOR");
  if (!f || probs->empty()) return;
  static std::once_flag once;
  static std::vector<double> n0[2], n1[2];
  std::call_once(once, [&] {
    for (int k = 0; k < 2; ++k) n0[k].assign(kMaxContexts, 0), n1[k].assign(kMaxContexts, 0);
    FILE* fp = std::fopen(f, "r");
    if (!fp) return;
    int ch, ctx;
    double a, b;
    while (std::fscanf(fp, "%d %d %lf %lf", &ch, &ctx, &a, &b) == 4) {
      n0[ch > 0][ctx] += a;
      n1[ch > 0][ctx] += b;
    }
    std::fclose(fp);
  });
  const int cls = g_channel > 0;
  const char* cs = std::getenv("FVV_PRIOR_COUNT");
  const int count = cs ? std::atoi(cs) : 2;
  for (int i = 0; i < kMaxContexts; ++i) {
    const double n = n0[cls][i] + n1[cls][i];
    if (n < 1) continue;
    int p = int(32768.0 * (n0[cls][i] + 0.5) / (n + 1.0));
    p = p < 64 ? 64 : p > 32704 ? 32704 : p;
    (*probs)[i].p0 = uint16_t(p);
    (*probs)[i].count = uint8_t(count);
  }
}
inline void Dump(const std::vector<uint32_t>& c0, const std::vector<uint32_t>& c1) {
  const char* f = std::getenv("FVV_DUMP");
  if (!f) return;
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
  FILE* fp = std::fopen(f, "a");
  for (size_t i = 0; i < c0.size(); ++i)
    if (c0[i] + c1[i]) std::fprintf(fp, "%d %zu %u %u\n", g_channel, i, c0[i], c1[i]);
  std::fclose(fp);
}
}  // namespace prior_exp
}  // namespace fvv
namespace fvv { namespace prior_exp {
inline int HpBits() { static int p = std::getenv("FVV_HP") ? std::atoi(std::getenv("FVV_HP")) : 0; return p; }
} }
