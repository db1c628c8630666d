#include "mesh/mesh_io.h"

#include <openssl/evp.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace mesh4d::mesh {
namespace {

constexpr char kMagic[8] = {'M', 'E', 'S', 'H', '4', 'D', '\0', '\n'};
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kChecksumBytes = 32;

// Little-endian writers and readers, independent of the host's byte order.
struct Writer {
  std::vector<std::uint8_t>& out;
  void u8(std::uint8_t v) { out.push_back(v); }
  void u16(std::uint16_t v) { u8(v & 0xff), u8(v >> 8); }
  void u32(std::uint32_t v) { u16(v & 0xffff), u16(v >> 16); }
  void u64(std::uint64_t v) { u32(v & 0xffffffffu), u32(v >> 32); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  void pad8() {
    while (out.size() % 8) u8(0);
  }
};

struct Reader {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;
  void need(std::size_t n, const char* what) {
    if (size - at < n)
      throw MeshFormatError(std::string("truncated .m4d data: no room for ") + what);
  }
  std::uint8_t u8() { return data[at++]; }
  std::uint16_t u16() {
    const std::uint16_t lo = u8();
    return static_cast<std::uint16_t>(lo | (u8() << 8));
  }
  std::uint32_t u32() {
    const std::uint32_t lo = u16();
    return lo | (std::uint32_t{u16()} << 16);
  }
  std::uint64_t u64() {
    const std::uint64_t lo = u32();
    return lo | (std::uint64_t{u32()} << 32);
  }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  // Padding and reserved bytes are zero: a reader that skipped them would accept files that a
  // writer never makes, and a later format could not give them a meaning.
  void zeros_until(std::size_t end, const char* what) {
    for (; at < end; ++at)
      if (data[at] != 0) throw MeshFormatError(std::string("non-zero ") + what + " in .m4d");
  }
  void pad8() { zeros_until((at + 7) / 8 * 8, "padding"); }
};

std::size_t padded(std::size_t n) {
  return (n + 7) / 8 * 8;
}

// A periodic mesh's twins (ids in range): each one's later vertex exactly one period after its
// earlier one, at or past the period's end, and glued once; no earlier vertex is itself a
// later one (one period per seam). `fail` throws with what is wrong.
template <class Fail>
void check_twins(const Mesh4& mesh, Fail fail) {
  std::vector<std::uint8_t> later_seen(mesh.vertices.size(), 0);
  for (const auto& [later, earlier] : mesh.periodic_twins) {
    if (later_seen[later]++) fail("a vertex glued twice at the seam");
    Point4 p = mesh.vertices[earlier];
    p[3] += mesh.period;
    if (p != mesh.vertices[later]) fail("periodic twins not one period apart");
    if (mesh.vertices[later][3] < mesh.period_start + mesh.period)
      fail("a periodic twin before the end of the period");
  }
  for (const auto& [later, earlier] : mesh.periodic_twins)
    if (later_seen[earlier]) fail("a periodic twin glued to a vertex past the period");
}

}  // namespace

std::array<std::uint8_t, 32> sha256(const std::uint8_t* data, std::size_t size) {
  std::array<std::uint8_t, 32> digest{};
  unsigned int length = 0;
  if (EVP_Digest(data, size, digest.data(), &length, EVP_sha256(), nullptr) != 1 || length != 32)
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  return digest;
}

std::string sha256_hex(const std::uint8_t* data, std::size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (std::uint8_t b : sha256(data, size)) out += kDigits[b >> 4], out += kDigits[b & 15];
  return out;
}

std::vector<std::uint8_t> encode_m4d(const Mesh4& mesh) {
  const std::size_t nv = mesh.vertices.size(), np = mesh.pentatopes.size(),
                    nb = mesh.boundary.size();
  if (mesh.vertex_kinds.size() != nv) throw std::invalid_argument("one vertex kind per vertex");
  if (mesh.labels.size() != np) throw std::invalid_argument("one label per pentatope");
  for (const Point4& p : mesh.vertices)
    for (double c : p)
      if (!std::isfinite(c)) throw std::invalid_argument("non-finite vertex coordinate");
  for (std::size_t i = 0; i < np; ++i) {
    for (std::uint32_t v : mesh.pentatopes[i])
      if (v >= nv) throw std::invalid_argument("pentatope vertex id out of range");
    if (mesh.labels[i] == 0) throw std::invalid_argument("pentatope with label 0 (background)");
  }
  for (const auto& b : mesh.boundary) {
    for (std::uint32_t v : b.vertices)
      if (v >= nv) throw std::invalid_argument("boundary vertex id out of range");
    if (b.pentatope >= np) throw std::invalid_argument("boundary pentatope out of range");
  }
  if (mesh.periodic()) {
    if (!std::isfinite(mesh.period_start) || !std::isfinite(mesh.period))
      throw std::invalid_argument("non-finite period");
    for (const auto& [later, earlier] : mesh.periodic_twins)
      if (later >= nv || earlier >= nv)
        throw std::invalid_argument("periodic twin vertex id out of range");
    check_twins(mesh, [](const char* what) { throw std::invalid_argument(what); });
  } else if (!mesh.periodic_twins.empty()) {
    throw std::invalid_argument("periodic twins without a period");
  }

  std::vector<std::uint8_t> out;
  out.reserve(kHeaderBytes + nv * 33 + np * 22 + nb * 24 + 64);
  Writer w{out};
  for (char c : kMagic) w.u8(static_cast<std::uint8_t>(c));
  w.u32(kM4dVersion);
  w.u32(mesh.periodic() ? kPeriodicTimeFlag : 0);
  w.u64(nv);
  w.u64(np);
  w.u64(nb);
  while (out.size() < kHeaderBytes) w.u8(0);
  for (const Point4& p : mesh.vertices)
    for (double c : p) w.f64(c);
  for (VertexKind k : mesh.vertex_kinds) w.u8(static_cast<std::uint8_t>(k));
  w.pad8();
  for (const auto& p : mesh.pentatopes)
    for (std::uint32_t v : p) w.u32(v);
  w.pad8();
  for (Label l : mesh.labels) w.u16(l);
  w.pad8();
  for (const auto& b : mesh.boundary) {
    for (std::uint32_t v : b.vertices) w.u32(v);
    w.u32(b.pentatope);
    w.u16(b.inner);
    w.u16(b.outer);
  }
  if (mesh.periodic()) {
    w.f64(mesh.period_start);
    w.f64(mesh.period);
    w.u64(mesh.periodic_twins.size());
    for (const auto& [later, earlier] : mesh.periodic_twins) w.u32(later), w.u32(earlier);
  }
  const auto digest = sha256(out.data(), out.size());
  out.insert(out.end(), digest.begin(), digest.end());
  return out;
}

Mesh4 decode_m4d(const std::uint8_t* data, std::size_t size) {
  if (size < kHeaderBytes + kChecksumBytes) throw MeshFormatError("too short to be a .m4d mesh");
  if (std::memcmp(data, kMagic, sizeof kMagic) != 0)
    throw MeshFormatError("not a .m4d mesh (bad magic number)");
  Reader r{data, size - kChecksumBytes, sizeof kMagic};
  const std::uint32_t version = r.u32();
  if (version != kM4dVersion) {
    std::ostringstream s;
    s << ".m4d version " << version << " is not supported (this reader knows version "
      << kM4dVersion << ")";
    throw MeshFormatError(s.str());
  }
  const std::uint32_t flags = r.u32();
  if (flags & ~kPeriodicTimeFlag) {
    std::ostringstream s;
    s << ".m4d flags 0x" << std::hex << (flags & ~kPeriodicTimeFlag)
      << " are not known to this reader";
    throw MeshFormatError(s.str());
  }
  const bool periodic = flags & kPeriodicTimeFlag;
  const std::uint64_t nv = r.u64(), np = r.u64(), nb = r.u64();
  // The section sizes must add up exactly before anything is allocated from them. The periodic
  // section's twin count is read where it lies, once the rest is known to fit.
  double expected = double(kHeaderBytes) + double(padded(nv * 33)) + double(padded(np * 20)) +
                    double(padded(np * 2)) + double(nb * 24);
  std::uint64_t nt = 0;
  if (periodic && expected + 24 <= double(size - kChecksumBytes) && nv <= (1ull << 32) &&
      np <= (1ull << 40) && nb <= (1ull << 40)) {
    Reader at_twins{data, size - kChecksumBytes, static_cast<std::size_t>(expected) + 16};
    nt = at_twins.u64();
    expected += 24 + 8 * double(nt);
  } else if (periodic) {
    expected += 24;
  }
  if (nv > (1ull << 32) || np > (1ull << 40) || nb > (1ull << 40) || nt > nv ||
      expected != double(size - kChecksumBytes))
    throw MeshFormatError("inconsistent .m4d sizes: the header's counts do not match the length");
  const auto digest = sha256(data, size - kChecksumBytes);
  if (std::memcmp(digest.data(), data + size - kChecksumBytes, kChecksumBytes) != 0)
    throw MeshFormatError(".m4d checksum mismatch: the mesh is corrupted");

  Mesh4 mesh;
  r.zeros_until(kHeaderBytes, "reserved header bytes");
  mesh.vertices.resize(nv);
  for (auto& p : mesh.vertices)
    for (double& c : p)
      if (!std::isfinite(c = r.f64()))
        throw MeshFormatError("non-finite vertex coordinate in .m4d");
  mesh.vertex_kinds.resize(nv);
  for (auto& k : mesh.vertex_kinds) {
    const std::uint8_t v = r.u8();
    if (v < 1 || v > 3) throw MeshFormatError("unknown vertex kind in .m4d");
    k = static_cast<VertexKind>(v);
  }
  r.pad8();
  mesh.pentatopes.resize(np);
  for (auto& p : mesh.pentatopes)
    for (auto& v : p) {
      v = r.u32();
      if (v >= nv) throw MeshFormatError("pentatope vertex id out of range in .m4d");
    }
  r.pad8();
  mesh.labels.resize(np);
  for (auto& l : mesh.labels)
    if ((l = r.u16()) == 0) throw MeshFormatError("pentatope with label 0 (background) in .m4d");
  r.pad8();
  mesh.boundary.resize(nb);
  for (auto& b : mesh.boundary) {
    for (auto& v : b.vertices) {
      v = r.u32();
      if (v >= nv) throw MeshFormatError("boundary vertex id out of range in .m4d");
    }
    b.pentatope = r.u32();
    if (b.pentatope >= np) throw MeshFormatError("boundary pentatope out of range in .m4d");
    b.inner = r.u16();
    b.outer = r.u16();
  }
  if (periodic) {
    mesh.period_start = r.f64();
    mesh.period = r.f64();
    if (!std::isfinite(mesh.period_start) || !std::isfinite(mesh.period) || !(mesh.period > 0))
      throw MeshFormatError("periodic .m4d with a period that is not finite and positive");
    mesh.periodic_twins.resize(r.u64());
    for (auto& [later, earlier] : mesh.periodic_twins) {
      later = r.u32();
      earlier = r.u32();
      if (later >= nv || earlier >= nv)
        throw MeshFormatError("periodic twin vertex id out of range in .m4d");
    }
    check_twins(mesh,
                [](const char* what) { throw MeshFormatError(std::string(what) + " in .m4d"); });
  }
  return mesh;
}

void write_m4d(const Mesh4& mesh, const std::string& path) {
  const auto bytes = encode_m4d(mesh);
  // Written next to the target and renamed, so a reader never sees half a mesh.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp);
}

Mesh4 read_m4d(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshFormatError(path + ": cannot open");
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  try {
    return decode_m4d(bytes.data(), bytes.size());
  } catch (const MeshFormatError& e) {
    throw MeshFormatError(path + ": " + e.what());
  }
}

}  // namespace mesh4d::mesh
