#include "deployfx/multibody/checkpoint.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <Eigen/SparseCore>

#include "deployfx/multibody/data.hpp"
#include "deployfx/multibody/residual.hpp"

namespace deployfx::multibody {

void check_checkpoint(const Model& m, const Checkpoint& c) {
  const integrate::AlphaState& s = c.driver.state;
  const Eigen::Index nv = m.num_velocities();
  auto fail = [](const std::string& why) { throw std::invalid_argument("checkpoint: " + why); };
  m.check_state(s.q, s.v);
  if (s.vdot.size() != nv || s.a.size() != nv || s.base_accel.size() > nv ||
      (s.vdot_prev.size() != 0 && s.vdot_prev.size() != nv) || c.accepted_q.size() != s.q.size())
    fail("its accelerations' sizes do not fit this model");
  if (c.driver.contact_bounds.error.size() != 0 && c.driver.contact_bounds.error.size() != nv)
    fail("its contact step bounds do not fit this model");
  if (c.locks.size() != static_cast<std::size_t>(m.num_hinges())) fail("it holds another number of hinges");
  const Data fresh(m);  // the lock kinds this model's histories take
  for (std::size_t k = 0; k < c.locks.size(); ++k)
    if (c.locks[k].index() != fresh.locks[k].index()) fail("hinge " + std::to_string(k) + "'s lock is of another kind");
  auto tracker_fits = [&](const joint::ImpactTracker& t) {
    const joint::ImpactTracker::Snapshot x = t.snapshot();
    if ((x.open && x.index >= c.impacts.size()) || x.n < 0 || x.n > 3) fail("an impact tracker points past the records");
  };
  for (std::size_t k = 0; k < c.locks.size(); ++k) {
    if (const auto* h = std::get_if<joint::LockHistory>(&c.locks[k])) {
      tracker_fits(h->stop_track), tracker_fits(h->latch_track);
    } else {
      const auto& g = std::get<joint::PinGrooveHistory>(c.locks[k]);
      if (g.facets.size() != std::get<joint::PinGrooveHistory>(fresh.locks[k]).facets.size())
        fail("hinge " + std::to_string(k) + "'s groove has another number of facets");
      for (const joint::FacetContact& f : g.facets) tracker_fits(f.track);
    }
  }
  for (const joint::Impact& i : c.impacts)
    if (i.hinge < 0 || i.hinge >= m.num_hinges()) fail("an impact record names no hinge of this model");
  if (!(c.driver.k >= 0)) fail("its output step count is negative");
  const integrate::GeneralizedAlpha::Solver& sv = c.driver.solver;
  if (sv.full_steps < 0 || sv.elastic_refreshes < 0) fail("its Newton counters are negative");
  if (sv.h > 0) {
    const integrate::BlockMatrix& S = sv.S;
    const Eigen::Index nb = S.A.rows(), ne = S.E.rows(), nc = m.num_conserved();
    if (S.A.cols() != nb || S.B.rows() != nb || S.B.cols() != ne || S.C.rows() != ne || S.C.cols() != nb ||
        S.E.cols() != ne || nb + ne != nv ||
        (nc > 0 && (sv.momentum_jacobian.rows() != nc || sv.momentum_jacobian.cols() != nv)))
      fail("its Newton matrix does not fit this model");
  }
  if (sv.slaved_h > 0) {
    const auto slaved = static_cast<Eigen::Index>(slaved_velocities(m).size());
    const Eigen::SparseMatrix<double>& E = sv.slaved_block.E;
    if (E.rows() != slaved || E.cols() != slaved || !E.isCompressed())
      fail("its slaved block does not fit this model");
  }
}

// The binary image: a magic word and version, then every field in a fixed order, numbers in this
// machine's representation (a checkpoint resumes on the machine kind that wrote it).
namespace {

constexpr char kMagic[8] = {'D', 'F', 'X', 'C', 'K', 'P', 'T', '5'};  // 5: with the slaved block (session 29)

struct Writer {
  std::string out;
  template <class T>
  void put(const T& x) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&x), sizeof(T));
  }
  void put(const Eigen::VectorXd& v) {
    put(static_cast<std::int64_t>(v.size()));
    out.append(reinterpret_cast<const char*>(v.data()), sizeof(double) * static_cast<std::size_t>(v.size()));
  }
  void put(const Eigen::MatrixXd& M) {
    put(static_cast<std::int64_t>(M.rows())), put(static_cast<std::int64_t>(M.cols()));
    out.append(reinterpret_cast<const char*>(M.data()), sizeof(double) * static_cast<std::size_t>(M.size()));
  }
  // A compressed sparse matrix as its raw arrays (the order of its entries kept).
  void put(const Eigen::SparseMatrix<double>& E) {
    Eigen::SparseMatrix<double> c = E;
    c.makeCompressed();
    put(static_cast<std::int64_t>(c.rows())), put(static_cast<std::int64_t>(c.cols()));
    put(static_cast<std::int64_t>(c.nonZeros()));
    using I = Eigen::SparseMatrix<double>::StorageIndex;
    out.append(reinterpret_cast<const char*>(c.outerIndexPtr()), sizeof(I) * static_cast<std::size_t>(c.outerSize() + 1));
    out.append(reinterpret_cast<const char*>(c.innerIndexPtr()), sizeof(I) * static_cast<std::size_t>(c.nonZeros()));
    out.append(reinterpret_cast<const char*>(c.valuePtr()), sizeof(double) * static_cast<std::size_t>(c.nonZeros()));
  }
};

struct Reader {
  const std::string& in;
  std::size_t at = 0;
  void need(std::size_t n) const {
    if (n > in.size() - at) throw std::invalid_argument("checkpoint: the data is truncated or malformed");
  }
  template <class T>
  void get(T& x) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    std::memcpy(&x, in.data() + at, sizeof(T));
    at += sizeof(T);
  }
  void get(Eigen::VectorXd& v) {
    std::int64_t n = 0;
    get(n);
    if (n < 0 || n > (1LL << 40)) throw std::invalid_argument("checkpoint: the data is truncated or malformed");
    need(sizeof(double) * static_cast<std::size_t>(n));
    v.resize(n);
    std::memcpy(v.data(), in.data() + at, sizeof(double) * static_cast<std::size_t>(n));
    at += sizeof(double) * static_cast<std::size_t>(n);
  }
  [[noreturn]] static void malformed() {
    throw std::invalid_argument("checkpoint: the data is truncated or malformed");
  }
  template <class T>
  void raw(T* p, std::int64_t n) {
    need(sizeof(T) * static_cast<std::size_t>(n));
    std::memcpy(p, in.data() + at, sizeof(T) * static_cast<std::size_t>(n));
    at += sizeof(T) * static_cast<std::size_t>(n);
  }
  void get(Eigen::MatrixXd& M) {
    std::int64_t r = 0, c = 0;
    get(r), get(c);
    if (r < 0 || c < 0 || r > (1 << 24) || c > (1 << 24)) malformed();
    need(sizeof(double) * static_cast<std::size_t>(r * c));
    M.resize(r, c);
    raw(M.data(), r * c);
  }
  void get(Eigen::SparseMatrix<double>& E) {
    using I = Eigen::SparseMatrix<double>::StorageIndex;
    std::int64_t r = 0, c = 0, nnz = 0;
    get(r), get(c), get(nnz);
    if (r < 0 || c < 0 || nnz < 0 || r > (1 << 28) || c > (1 << 28) || nnz > r * c) malformed();
    need((sizeof(I) + sizeof(double)) * static_cast<std::size_t>(nnz) + sizeof(I) * static_cast<std::size_t>(c + 1));
    E.resize(r, c);
    E.resizeNonZeros(nnz);
    raw(E.outerIndexPtr(), c + 1);
    raw(E.innerIndexPtr(), nnz);
    raw(E.valuePtr(), nnz);
    // A malformed pattern must not reach the solver: outer indices rising from 0 to nnz, inner ones in range.
    const I* o = E.outerIndexPtr();
    if (o[0] != 0 || o[c] != nnz) malformed();
    for (std::int64_t j = 0; j < c; ++j)
      if (o[j + 1] < o[j]) malformed();
    for (std::int64_t k = 0; k < nnz; ++k)
      if (E.innerIndexPtr()[k] < 0 || E.innerIndexPtr()[k] >= r) malformed();
  }
  std::int64_t count() {
    std::int64_t n = 0;
    get(n);
    if (n < 0 || n > (1LL << 32)) throw std::invalid_argument("checkpoint: the data is truncated or malformed");
    return n;
  }
};

void put_tracker(Writer& w, const joint::ImpactTracker& t) { w.put(t.snapshot()); }
void get_tracker(Reader& r, joint::ImpactTracker& t) {
  joint::ImpactTracker::Snapshot s;
  r.get(s);
  t.restore(s);
}

}  // namespace

std::string Checkpoint::to_bytes() const {
  Writer w;
  w.out.append(kMagic, sizeof kMagic);
  const integrate::AlphaState& s = driver.state;
  w.put(s.t);
  w.put(s.q), w.put(s.v), w.put(s.vdot), w.put(s.a), w.put(s.base_accel), w.put(s.vdot_prev);
  w.put(s.h_prev);
  w.put(driver.t0), w.put(static_cast<std::int64_t>(driver.k)), w.put(driver.h_try), w.put(driver.h_contact);
  w.put(driver.contact_bounds.error), w.put(driver.contact_bounds.min_step);
  const integrate::GeneralizedAlpha::Solver& solver = driver.solver;
  w.put(static_cast<std::int32_t>(solver.full_steps)), w.put(static_cast<std::int32_t>(solver.elastic_refreshes));
  w.put(solver.h);
  w.put(solver.S.A), w.put(solver.S.B), w.put(solver.S.C), w.put(solver.S.E), w.put(solver.momentum_jacobian);
  w.put(solver.slaved_h), w.put(solver.slaved_block.E);
  w.put(static_cast<std::int64_t>(locks.size()));
  for (const joint::LockState& L : locks) {
    w.put(static_cast<std::int32_t>(L.index()));
    if (const auto* h = std::get_if<joint::LockHistory>(&L)) {
      w.put(h->latched), w.put(h->stop_contact), w.put(h->latch_contact), w.put(h->stop_inside),
          w.put(h->latch_inside), w.put(h->stop_v0), w.put(h->latch_v0), w.put(h->stop_T), w.put(h->latch_T),
          w.put(h->stop_resolution), w.put(h->latch_resolution);
      put_tracker(w, h->stop_track), put_tracker(w, h->latch_track);
    } else {
      const auto& g = std::get<joint::PinGrooveHistory>(L);
      w.put(static_cast<std::int64_t>(g.facets.size()));
      for (const joint::FacetContact& f : g.facets) {
        w.put(f.armed), w.put(f.closed), w.put(f.inside), w.put(f.v0), w.put(f.T), w.put(f.resolution);
        put_tracker(w, f.track);
      }
      w.put(static_cast<std::int32_t>(g.support));
    }
  }
  w.put(static_cast<std::int64_t>(impacts.size()));
  for (const joint::Impact& i : impacts) w.put(i);
  w.put(accepted_q);
  w.out.append(kMagic, sizeof kMagic);  // an end marker
  return w.out;
}

Checkpoint Checkpoint::from_bytes(const std::string& bytes) {
  if (bytes.size() < 2 * sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::invalid_argument("checkpoint: not a deployfx checkpoint (or of another version)");
  Reader r{bytes, sizeof kMagic};
  Checkpoint c;
  integrate::AlphaState& s = c.driver.state;
  r.get(s.t);
  r.get(s.q), r.get(s.v), r.get(s.vdot), r.get(s.a), r.get(s.base_accel), r.get(s.vdot_prev);
  r.get(s.h_prev);
  std::int64_t k = 0;
  std::int32_t full = 0;
  r.get(c.driver.t0), r.get(k), r.get(c.driver.h_try), r.get(c.driver.h_contact);
  r.get(c.driver.contact_bounds.error), r.get(c.driver.contact_bounds.min_step), r.get(full);
  c.driver.k = static_cast<long>(k);
  integrate::GeneralizedAlpha::Solver& solver = c.driver.solver;
  solver.full_steps = full;
  std::int32_t refreshes = 0;
  r.get(refreshes);
  solver.elastic_refreshes = refreshes;
  r.get(solver.h);
  r.get(solver.S.A), r.get(solver.S.B), r.get(solver.S.C), r.get(solver.S.E), r.get(solver.momentum_jacobian);
  r.get(solver.slaved_h), r.get(solver.slaved_block.E);
  const Eigen::Index slaved = solver.slaved_block.E.rows();
  solver.slaved_block.A.resize(0, 0), solver.slaved_block.B.resize(0, slaved), solver.slaved_block.C.resize(slaved, 0);
  c.locks.resize(static_cast<std::size_t>(r.count()));
  for (joint::LockState& L : c.locks) {
    std::int32_t kind = 0;
    r.get(kind);
    if (kind == 0) {
      joint::LockHistory h;
      r.get(h.latched), r.get(h.stop_contact), r.get(h.latch_contact), r.get(h.stop_inside), r.get(h.latch_inside),
          r.get(h.stop_v0), r.get(h.latch_v0), r.get(h.stop_T), r.get(h.latch_T), r.get(h.stop_resolution),
          r.get(h.latch_resolution);
      get_tracker(r, h.stop_track), get_tracker(r, h.latch_track);
      L = h;
    } else if (kind == 1) {
      joint::PinGrooveHistory g;
      g.facets.resize(static_cast<std::size_t>(r.count()));
      for (joint::FacetContact& f : g.facets) {
        r.get(f.armed), r.get(f.closed), r.get(f.inside), r.get(f.v0), r.get(f.T), r.get(f.resolution);
        get_tracker(r, f.track);
      }
      std::int32_t support = 0;
      r.get(support);
      g.support = support;
      L = g;
    } else {
      throw std::invalid_argument("checkpoint: the data is truncated or malformed");
    }
  }
  c.impacts.resize(static_cast<std::size_t>(r.count()));
  for (joint::Impact& i : c.impacts) r.get(i);
  r.get(c.accepted_q);
  r.need(sizeof kMagic);
  if (std::memcmp(bytes.data() + r.at, kMagic, sizeof kMagic) != 0 || r.at + sizeof kMagic != bytes.size())
    throw std::invalid_argument("checkpoint: the data is truncated or malformed");
  return c;
}

}  // namespace deployfx::multibody
