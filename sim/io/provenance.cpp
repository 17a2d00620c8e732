// Provenance of a run (provenance.hpp): SHA-256 (FIPS 180-4), the date, the command line, the inputs.
#include "sim/io/provenance.hpp"

#include <array>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/io/json.hpp"

namespace lg {
namespace {

// SHA-256 over a whole message (FIPS 180-4, section 6.2).
class Sha256 {
 public:
  std::array<uint8_t, 32> digest(const std::string& m) {
    uint64_t bits = static_cast<uint64_t>(m.size()) * 8;
    std::string msg = m;
    msg.push_back(static_cast<char>(0x80));
    while (msg.size() % 64 != 56) msg.push_back('\0');
    for (int i = 7; i >= 0; --i) msg.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
    for (size_t off = 0; off < msg.size(); off += 64) block(reinterpret_cast<const uint8_t*>(msg.data()) + off);
    std::array<uint8_t, 32> out{};
    for (int i = 0; i < 8; ++i)
      for (int b = 0; b < 4; ++b) out[4 * i + b] = static_cast<uint8_t>(h_[i] >> (24 - 8 * b));
    return out;
  }

 private:
  static uint32_t rotr(uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }
  void block(const uint8_t* p) {
    static constexpr uint32_t k[64] = {
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5, 0xd807aa98, 0x12835b01,
        0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc,
        0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147,
        0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
        0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116, 0x1e376c08,
        0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3, 0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208,
        0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};
    uint32_t w[64];
    for (int t = 0; t < 16; ++t)
      w[t] = (uint32_t(p[4 * t]) << 24) | (uint32_t(p[4 * t + 1]) << 16) | (uint32_t(p[4 * t + 2]) << 8) | uint32_t(p[4 * t + 3]);
    for (int t = 16; t < 64; ++t) {
      const uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
      const uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
      w[t] = w[t - 16] + s0 + w[t - 7] + s1;
    }
    uint32_t a = h_[0], b = h_[1], c = h_[2], d = h_[3], e = h_[4], f = h_[5], g = h_[6], h = h_[7];
    for (int t = 0; t < 64; ++t) {
      const uint32_t S1 = rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25);
      const uint32_t ch = (e & f) ^ (~e & g);
      const uint32_t t1 = h + S1 + ch + k[t] + w[t];
      const uint32_t S0 = rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22);
      const uint32_t maj = (a & b) ^ (a & c) ^ (b & c);
      const uint32_t t2 = S0 + maj;
      h = g;
      g = f;
      f = e;
      e = d + t1;
      d = c;
      c = b;
      b = a;
      a = t1 + t2;
    }
    h_[0] += a, h_[1] += b, h_[2] += c, h_[3] += d, h_[4] += e, h_[5] += f, h_[6] += g, h_[7] += h;
  }
  uint32_t h_[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
};

// An argument as a shell would need it: as it is where it is plain, else in single quotes.
std::string shellWord(const std::string& a) {
  if (!a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,+@%") == std::string::npos)
    return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

}  // namespace

std::string sha256Hex(const std::string& bytes) {
  const auto d = Sha256().digest(bytes);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (uint8_t b : d) {
    out += hex[b >> 4];
    out += hex[b & 15];
  }
  return out;
}

std::string fileSha256(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return "unreadable";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable";
  std::ostringstream s;
  s << in.rdbuf();
  return sha256Hex(s.str());
}

Provenance makeProvenance(const std::string& program, int argc, const char* const* argv, const std::vector<InputFile>& inputs) {
  Provenance p;
  p.program = program;
  p.version = buildVersion();
  p.commit = buildCommit();
  p.date = utcNow();
  for (int i = 0; i < argc; ++i) p.commandLine += (i ? " " : "") + shellWord(i == 0 ? program : std::string(argv[i]));
  for (const InputFile& f : inputs) {
    bool seen = false;
    for (const InputFile& g : p.inputs) seen = seen || g.path == f.path;
    if (seen) continue;
    InputFile h = f;
    h.sha256 = fileSha256(f.path);
    p.inputs.push_back(h);
  }
  return p;
}

std::vector<InputFile> sceneInputs(const Scene& scene) {
  namespace fs = std::filesystem;
  std::vector<InputFile> out{{"scene", scene.file, ""}};
  const fs::path dir = fs::path(scene.file).parent_path();
  for (const char* arr : {"force", "body", "joint", "stop"}) {
    const toml::array* a = scene.doc[arr].as_array();
    if (!a) continue;
    for (const auto& e : *a) {
      const toml::table* t = e.as_table();
      if (!t) continue;
      for (const auto& [k, v] : *t) {
        const std::string key(k.str());
        if (key.size() < 6 || key.compare(key.size() - 6, 6, "_table") != 0 || !v.is_string()) continue;
        fs::path p(*v.value<std::string>());
        if (p.is_relative()) p = dir / p;
        out.push_back({"table", p.lexically_normal().string(), ""});
      }
    }
  }
  return out;
}

std::string versionLine(const std::string& program) {
  return program + " " + buildVersion() + " (commit " + buildCommit() + ")";
}

std::string provenanceJson(const Provenance& p, const std::string& indent) {
  std::ostringstream o;
  o << indent << "\"provenance\": {\"program\": " << jsonString(p.program) << ", \"version\": " << jsonString(p.version)
    << ", \"commit\": " << jsonString(p.commit) << ", \"date_utc\": " << jsonString(p.date) << ",\n"
    << indent << "  \"command_line\": " << jsonString(p.commandLine) << ",\n" << indent << "  \"inputs\": [";
  for (size_t i = 0; i < p.inputs.size(); ++i)
    o << (i ? ", " : "") << "{\"role\": " << jsonString(p.inputs[i].role) << ", \"path\": " << jsonString(p.inputs[i].path)
      << ", \"sha256\": " << jsonString(p.inputs[i].sha256) << "}";
  o << "]}";
  return o.str();
}

std::string provenanceMarkdown(const Provenance& p) {
  std::ostringstream o;
  o << "## Provenance\n\n- program: `" << p.program << "` " << p.version << ", commit `" << p.commit << "`\n- run: "
    << p.date << " (UTC)\n- command line: `" << p.commandLine << "`\n- inputs (SHA-256):\n";
  for (const auto& f : p.inputs) o << "  - " << f.role << " `" << f.path << "`: `" << f.sha256 << "`\n";
  return o.str();
}

std::string provenanceComment(const Provenance& p) {
  std::ostringstream o;
  o << "# Written by " << p.program << " " << p.version << " (commit " << p.commit << ") on " << p.date << " (UTC)\n"
    << "# command line: " << p.commandLine << "\n";
  for (const auto& f : p.inputs) o << "# " << f.role << " " << f.path << " sha256 " << f.sha256 << "\n";
  return o.str();
}

std::string stampJson(const std::string& json, const Provenance* p) {
  if (!p || json.rfind("{\n", 0) != 0) return json;
  return "{\n" + provenanceJson(*p) + ",\n" + json.substr(2);
}

std::string stampMarkdown(const std::string& md, const Provenance* p) {
  if (!p) return md;
  const auto title = md.rfind("# ", 0) == 0 ? md.find('\n') : std::string::npos;
  if (title == std::string::npos) return provenanceMarkdown(*p) + "\n" + md;
  return md.substr(0, title + 1) + "\n" + provenanceMarkdown(*p) + md.substr(title + 1);
}

std::string stampToml(const std::string& toml, const Provenance* p) { return p ? provenanceComment(*p) + toml : toml; }

}  // namespace lg
