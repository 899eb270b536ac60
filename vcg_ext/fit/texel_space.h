#pragma once
/// \file texel_space.h
/// Internal to vcg_ext/fit: the atlas's texel bookkeeping shared by the bake (bake.cpp), the texel
/// fit and the displaced layer (texel_fit.cpp) and the tessellation (tessellate.cpp): the bilinear
/// tile filter, 16-bit quantization, the seamless atlas's free values, layout checks.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vcg_ext/fit/bake.h"

namespace vcgext {
namespace fitdetail {

inline std::uint64_t EdgeKey(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

// (u,v) numerators (over den) of the point at edge fraction p/den of side e of a patch, going
// around the patch: e0 c0->c1 (v=0), e1 c1->c2 (u=1), e2 c2->c3 (v=1), e3 c3->c0 (u=0).
void SidePoint(int e, int p, int den, int* i, int* j);

// The bilinear texture filter of a tile with T texel intervals per side (texel (i,j) at
// (u,v) = (i/T, j/T)): the cell's lower texel and the weights of texels (i,j), (i+1,j), (i,j+1),
// (i+1,j+1). DisplacedSurface and the texel fit must filter identically.
struct TileCell {
  int i, j;
  double w[4];
};
TileCell CellAt(const Eigen::Vector2d& uv, int T);

// 16-bit quantization over the tiles actually used: disp ≈ offset + scale · q16.
void Quantize(DisplacementAtlas& a);

// The free values of a seamless atlas: one unknown per surface point that some tile's texel
// stands for exactly — control vertices (tile corners), the texels of each shared edge at the
// coarser of its two tiles' resolutions, tile interiors. Every texel is one unknown or (a finer
// tile's extra edge texel) the linear interpolation of two neighbouring edge unknowns.
class TexelSpace {
 public:
  struct Term {
    int id[2];
    double w[2];
    int n;
  };
  TexelSpace(const LimitSurface& ls, const DisplacementAtlas& a);
  int NumUnknowns() const { return n_; }
  const Term& At(int f, int i, int j) const { return terms_[offset_[f] + j * a_.tileR[f] + i]; }
  // Unknowns from the texels that stand for them exactly (the mean over the tiles sharing one).
  Eigen::VectorXd Gather(const DisplacementAtlas& a) const {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(n_), cnt = Eigen::VectorXd::Zero(n_);
    ForEach([&](int f, int i, int j, const Term& t) {
      if (t.n != 1) return;
      sum[t.id[0]] += a.disp[a.Pixel(f, i, j)];
      cnt[t.id[0]] += 1;
    });
    return sum.cwiseQuotient(cnt.cwiseMax(1.0));
  }
  // Writes every texel of every tile from the unknowns.
  void Scatter(const Eigen::VectorXd& d, DisplacementAtlas& a) const {
    ForEach([&](int f, int i, int j, const Term& t) {
      double v = 0;
      for (int q = 0; q < t.n; ++q) v += t.w[q] * d[t.id[q]];
      a.disp[a.Pixel(f, i, j)] = float(v);
    });
  }

 private:
  template <class Fn>
  void ForEach(Fn fn) const {
    for (int f = 0; f + 1 < int(offset_.size()); ++f)
      for (int j = 0; j < a_.tileR[f]; ++j)
        for (int i = 0; i < a_.tileR[f]; ++i) fn(f, i, j, At(f, i, j));
  }
  const DisplacementAtlas& a_;
  std::vector<size_t> offset_;
  std::vector<Term> terms_;
  int n_ = 0;
};


// The atlas's tile sizes are a valid layout for a surface of nF patches: one tile per patch,
// inside the image, and (for seamless edges) 2^k+1 texels when they differ.
bool LayoutOk(const DisplacementAtlas& a, int nF);

}  // namespace fitdetail
}  // namespace vcgext
