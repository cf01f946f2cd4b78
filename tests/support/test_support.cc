#include "test_support.h"

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"

#include <cstdlib>
#include <cstring>
#include <array>
#include <random>

#include <zlib.h>

namespace gmwm::test {

std::optional<std::filesystem::path> shared_data_dir() {
  std::filesystem::path p;
  if (const char* env = std::getenv("GMWM_SHARED_DATA"); env && *env) {
    p = env;
  } else {
    p = std::filesystem::path(GMWM_SOURCE_DIR) / ".." / "shared" / "data";
  }
  if (std::filesystem::exists(p / "adis_16405_imu1.csv.gz")) return std::filesystem::canonical(p);
  return std::nullopt;
}

std::string shared_data_file(const std::string& name) {
  auto d = shared_data_dir();
  return d ? (*d / name).string() : std::string();
}

std::string gzip_member(const std::string& text) {
  z_stream zs{};
  deflateInit2(&zs, Z_BEST_COMPRESSION, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&zs, static_cast<uLong>(text.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

std::filesystem::path temp_dir(const std::string& tag) {
  std::random_device rd;
  auto p = std::filesystem::temp_directory_path() / ("gmwm_test_" + tag + "_" + std::to_string(rd()));
  std::filesystem::create_directories(p);
  return p;
}

std::vector<WaveletVariance> simulated_replicates(const std::string& spec, const std::vector<int>& log2n,
                                                  std::uint64_t seed) {
  const Model m = parse_model(spec);
  std::vector<WaveletVariance> out;
  for (std::size_t k = 0; k < log2n.size(); ++k) {
    const std::int64_t n = std::int64_t{1} << log2n[k];
    const auto x = simulate(m, m.given_values(), n, seed, k);
    out.push_back(classical_wv(x.data(), n));
  }
  return out;
}

namespace {

// Little-endian byte packing, as the ULog specification states.
struct Bytes {
  std::vector<unsigned char> b;
  template <typename T>
  void put(T v) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    b.insert(b.end(), raw, raw + sizeof(T));
  }
  void text(const std::string& s) { b.insert(b.end(), s.begin(), s.end()); }
  // A message: uint16 payload size, uint8 type, payload.
  void message(char type, const Bytes& payload) {
    put(static_cast<std::uint16_t>(payload.b.size()));
    put(static_cast<std::uint8_t>(type));
    b.insert(b.end(), payload.b.begin(), payload.b.end());
  }
};

constexpr const char* kSensorCombined =
    "sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;"
    "int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;uint32_t accelerometer_integral_dt;"
    "uint8_t accelerometer_clipping;uint8_t gyro_clipping;uint8_t accel_calibration_count;"
    "uint8_t gyro_calibration_count;";
constexpr const char* kSensorGyro =
    "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;"
    "float temperature;uint32_t error_count;uint8_t[3] clip_counter;uint8_t samples;uint8_t[4] _padding0;";

std::array<float, 6> combined(int i) {
  return {static_cast<float>(i) / 1024.0f,         -static_cast<float>(i) / 1024.0f,
          2.0f * static_cast<float>(i) / 1024.0f,  9.81f + static_cast<float>(i) / 4096.0f,
          0.5f + static_cast<float>(i % 7) / 8.0f, -static_cast<float>(i) / 2048.0f};
}

}  // namespace

std::vector<unsigned char> ulog_bytes(const UlogFixture& f) {
  Bytes out;
  for (int c : {0x55, 0x4C, 0x6F, 0x67, 0x01, 0x12, 0x35}) out.put(static_cast<std::uint8_t>(c));  // "ULog" 01 12 35
  out.put(static_cast<std::uint8_t>(1));                                                           // version
  out.put(f.t0);                                                                                   // start time, us
  Bytes flags;  // 'B': compat[8], incompat[8], appended offsets[3]
  for (int i = 0; i < 16; ++i) flags.put(static_cast<std::uint8_t>(0));
  for (int i = 0; i < 3; ++i) flags.put(static_cast<std::uint64_t>(0));
  out.message('B', flags);
  Bytes info;  // 'I': key length, "type name", value
  const std::string key = "char[7] sys_name";
  info.put(static_cast<std::uint8_t>(key.size()));
  info.text(key);
  info.text("PX4_SIM");
  out.message('I', info);
  for (const char* fmt : {kSensorCombined, kSensorGyro}) {
    Bytes b;
    b.text(fmt);
    out.message('F', b);
  }
  const auto subscribe = [&](std::uint8_t multi, std::uint16_t id, const std::string& name) {
    Bytes b;
    b.put(multi);
    b.put(id);
    b.text(name);
    out.message('A', b);
  };
  subscribe(0, 7, "sensor_combined");
  for (int k = 0; k < f.gyro_instances; ++k)
    subscribe(static_cast<std::uint8_t>(k), static_cast<std::uint16_t>(20 + k), "sensor_gyro");
  std::uint16_t combined_id = 7;
  for (int i = 0; i < f.samples; ++i) {
    if (i == f.resubscribe_at) {
      Bytes b;
      b.text(kSensorCombined);
      out.message('F', b);
      combined_id = 8;
      subscribe(0, combined_id, "sensor_combined");
    }
    const std::uint64_t t =
        f.stamps.empty() ? f.t0 + static_cast<std::uint64_t>(i) * f.step_us : f.stamps[static_cast<std::size_t>(i)];
    Bytes d;  // sensor_combined, 48 bytes
    d.put(combined_id);
    d.put(t);
    const auto v = combined(i);
    for (int a = 0; a < 3; ++a) d.put(v[static_cast<std::size_t>(a)]);
    d.put(static_cast<std::uint32_t>(f.step_us));
    d.put(static_cast<std::int32_t>(0));
    for (int a = 3; a < 6; ++a) d.put(v[static_cast<std::size_t>(a)]);
    d.put(static_cast<std::uint32_t>(f.step_us));
    for (int a = 0; a < 4; ++a) d.put(static_cast<std::uint8_t>(0));
    out.message('D', d);
    for (int k = 0; k < f.gyro_instances; ++k) {
      Bytes g;  // sensor_gyro, 48 bytes
      g.put(static_cast<std::uint16_t>(20 + k));
      g.put(t + 100);
      g.put(t);
      g.put(static_cast<std::uint32_t>(1000 + k));
      g.put(static_cast<float>(k) + static_cast<float>(i) / 512.0f);
      g.put(0.0f);
      g.put(0.0f);
      g.put(35.0f);
      g.put(static_cast<std::uint32_t>(0));
      for (int a = 0; a < 8; ++a) g.put(static_cast<std::uint8_t>(0));
      out.message('D', g);
    }
    if (i == f.samples / 2) {
      Bytes l;  // 'L': level, timestamp, text
      l.put(static_cast<std::uint8_t>('6'));
      l.put(t);
      l.text("[commander] armed");
      out.message('L', l);
      Bytes sync;
      for (int c : {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12}) sync.put(static_cast<std::uint8_t>(c));
      out.message('S', sync);
    }
  }
  return out.b;
}

std::vector<std::vector<double>> ulog_expected(const UlogFixture& f) {
  std::vector<std::vector<double>> out(6);
  for (int i = 0; i < f.samples; ++i) {
    const auto v = combined(i);
    for (std::size_t a = 0; a < 6; ++a) out[a].push_back(static_cast<double>(v[a]));
  }
  return out;
}

}  // namespace gmwm::test
