// libFuzzer target for the recording database's readers: the input bytes
// are written as a database file and read by every RunStore path that
// `runs list|show|export|replay`, `train --run` and `model fit --run` take
// (the run list, one run, its samples as rows and as columns, parameters,
// gaps, sensor health, link events, a CSV export, what a replay starts
// from: the reference read back from its JSON, the parameters' text, the
// step count). Any outcome but a value or a
// DbError/CliError is a finding: a crash, a sanitizer report, a hang.
// Build and run (clang only; see app/CMakeLists.txt):
//   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DNLSOFT_FUZZ=ON
//   cmake --build build-fuzz --target nlsoft-fuzz-run-store
//   build-fuzz/app/record/fuzz/nlsoft-fuzz-run-store -make_seeds=seeds   # recorded-run databases
//   build-fuzz/app/record/fuzz/nlsoft-fuzz-run-store -max_len=16384 -max_total_time=60 corpus seeds
//
// Random bytes are seldom a database: the seeds are small files the
// console's schema makes (512-byte pages, no WAL), which libFuzzer mutates
// page by page: counts, blob sizes, schema text, b-tree pages.
#include <sqlite3.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "app/record/csv_export.hpp"
#include "host/files/cli_error.hpp"
#include "app/record/run_store.hpp"
#include "app/record/schema.hpp"
#include "app/replay/recorded_start.hpp"

namespace nc = nlsoft::console;

namespace {

std::string g_path;  // the database file each input is written to

void exec(sqlite3* db, const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    std::fprintf(stderr, "seed: %s: %s\n", sql.substr(0, 60).c_str(), err ? err : "?");
    std::exit(1);
  }
}

// A blob literal of `count` floats.
std::string floats(int count, float first) {
  std::string hex = "x'";
  for (int i = 0; i < count; ++i) {
    float v = first + float(i);
    unsigned char b[4];
    std::memcpy(b, &v, 4);
    char h[9];
    std::snprintf(h, sizeof h, "%02x%02x%02x%02x", b[0], b[1], b[2], b[3]);
    hex += h;
  }
  return hex + "'";
}

// Databases as the console records them: a control run (n = 2, m = 1) with
// parameters, a gap, a link event and sensor health; an identification run
// with w = 3 sensors; and a file at schema v2, which a reader upgrades.
void make_seeds(const std::string& dir) {
  for (int seed = 0; seed < 3; ++seed) {
    const std::string path = dir + "/seed" + std::to_string(seed) + ".db";
    ::unlink(path.c_str());
    sqlite3* db = nullptr;
    if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) std::exit(1);
    exec(db, "PRAGMA page_size=512; PRAGMA journal_mode=DELETE;");
    const int version = seed == 2 ? 2 : nc::kSchemaVersion;
    for (int v = 1; v <= version; ++v) exec(db, nc::migration_sql(v));
    exec(db, "PRAGMA user_version=" + std::to_string(version));
    const bool ident = seed == 1;
    const int n = 2, m = 1, w = ident ? 3 : 0;
    exec(db, std::string("INSERT INTO runs(id,started_at,ended_at,platform,firmware,model_hash,param_hash,loop_rate_hz,"
                         "n,m,label,samples") +
                 (version >= 6 ? ",kind,w,excitation" : "") +
                 ") VALUES(1,'2026-01-01T00:00:00.000Z','2026-01-01T00:00:01.000Z','msd','nlsoft-posix 0.1.0',1,2,"
                 "100,2,1,'seed',4" +
                 (version >= 6 ? std::string(ident ? ",'ident',3,'{\"signal\":\"prbs\"}'" : ",'control',0,''") : "") +
                 ")");
    for (int k = 0; k < 4; ++k)
      exec(db, "INSERT INTO samples(id,step,time_us,y_ref,y_hat,y_true,u,cost,iterations,compute_us" +
                   std::string(version >= 6 ? ",l" : "") + ") VALUES(" + std::to_string((int64_t(1) << 32) + k) +
                   "," + std::to_string(k) + "," + std::to_string(k * 10000) + "," + floats(n, 1) + "," +
                   floats(n, 2) + "," + floats(n, 3) + "," + floats(m, 4) + ",0.5,3,12.5" +
                   (version >= 6 ? "," + (w ? floats(w, 5) : std::string("NULL")) : "") + ")");
    // The reference as the console records it: what a replay reads back.
    exec(db, "UPDATE runs SET reference='{\"kind\":\"swirl\",\"hold\":10,\"a\":4.0,\"b\":4.0,\"c\":4.0,"
             "\"center\":[0.0,0.0,4.0],\"omega\":0.006,\"lambda\":1040.0,\"scale\":1.0,\"levels\":[0.5]}'");
    exec(db, "INSERT INTO params(run_id,t,at_start,name,value) VALUES(1,0,1,'Q','1 2'),(1,0.5,0,'reference',"
             "'{\"kind\":\"swirl\"}')");
    exec(db, std::string("INSERT INTO gaps(run_id,t,after_k,lost_frames,reason") + (version >= 3 ? ",duration_s" : "") +
                 ") VALUES(1,'2026-01-01T00:00:00.500Z',1,3,'silence'" + (version >= 3 ? ",0.25" : "") + ")");
    exec(db, "INSERT INTO link_events(t,run_id,kind,detail) VALUES('2026-01-01T00:00:00.600Z',1,'reset','x')");
    if (version >= 7) exec(db, "INSERT INTO sensor_health(run_id,step,invalid,age_ms) VALUES(1,2,5,10)");
    exec(db, "VACUUM");
    sqlite3_close(db);
  }
}

void read_everything() {
  nc::RunStore store(g_path);
  for (const nc::RunRow& r : store.list()) {
    (void)store.run(r.id);
    const nc::RunSeries s = store.series(r.id);
    volatile float sink = 0;
    for (float v : s.y_ref) sink = sink + v;
    for (float v : s.l) sink = sink + v;
    store.for_each_sample(r.id, [&](const nc::Sample& x) {
      for (int i = 0; i < x.n; ++i) sink = sink + x.y_true()[i];
      for (int i = 0; i < x.m; ++i) sink = sink + x.u()[i];
      for (int i = 0; i < x.w; ++i) sink = sink + x.l[i];
    });
    (void)store.params(r.id);
    (void)store.gaps(r.id);
    (void)store.sensor_health(r.id);
    (void)store.link_events(r.id);
    nc::export_run_csv(store, r.id, "/dev/null");
    try {
      (void)nc::recorded_start(store, r.id);
    } catch (const nlsoft::host::CliError&) {
      // A run a replay refuses, in words: the other readers go on.
    }
  }
  (void)store.last_run_id();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  for (int i = 1; i < *argc; ++i)
    if (std::strncmp((*argv)[i], "-make_seeds=", 12) == 0) {
      make_seeds((*argv)[i] + 12);
      std::exit(0);
    }
  const char* tmp = std::getenv("TMPDIR");
  g_path = std::string(::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : tmp ? tmp : "/tmp") + "/nlsoft-fuzz-" +
           std::to_string(::getpid()) + ".db";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  for (const char* tail : {"", "-wal", "-shm", "-journal"}) ::unlink((g_path + tail).c_str());
  if (FILE* f = std::fopen(g_path.c_str(), "wb")) {
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
  }
  try {
    read_everything();
  } catch (const std::exception&) {
    // DbError, CliError: a file refused in words is what the readers owe.
  }
  return 0;
}
