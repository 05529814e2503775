// app/record/row_columns.hpp: one list of columns makes both the SELECT list
// and the reader, each field filled from its own column.
#include "app/record/row_columns.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>

namespace nlsoft::console {
namespace {

struct Row {
  int64_t id = 0;
  std::string name = "unset";
  uint32_t hash = 0;
  double rate = 0;
  int count = 0;
  std::optional<double> score;
};

const Column<Row> kFirst[] = {
    {"id", read_field<&Row::id>},
    {"ifnull(name,'')", read_field<&Row::name>},
    {"hash", read_field<&Row::hash>},
};
const Column<Row> kRest[] = {
    {"rate", read_field<&Row::rate>},
    {"count", read_field<&Row::count>},
    {"score", read_field<&Row::score>},
};

class RowColumns : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(sqlite3_open(":memory:", &db_), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db_,
                           "CREATE TABLE t(id INTEGER, name TEXT, hash INTEGER, rate REAL, count INTEGER, score REAL);"
                           "INSERT INTO t VALUES(7, NULL, 4294967295, 130.5, 3, NULL);"
                           "INSERT INTO t VALUES(8, 'msd', 1, 1000, -2, 0.25);",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
  }
  void TearDown() override { sqlite3_close(db_); }
  sqlite3* db_ = nullptr;
};

TEST_F(RowColumns, SelectListIsTheExpressionsInOrder) {
  EXPECT_EQ(select_list(kFirst), "id,ifnull(name,''),hash");
  EXPECT_EQ(select_list(kRest), "rate,count,score");
}

TEST_F(RowColumns, EachFieldIsFilledFromItsColumn) {
  const std::string sql = "SELECT " + select_list(kFirst) + "," + select_list(kRest) + " FROM t ORDER BY id";
  Stmt s(db_, sql.c_str());
  ASSERT_TRUE(s.step());
  Row a;
  EXPECT_EQ(read_columns(s, kRest, a, read_columns(s, kFirst, a)), 6);
  EXPECT_EQ(a.id, 7);
  EXPECT_EQ(a.name, "");
  EXPECT_EQ(a.hash, 0xFFFFFFFFu);
  EXPECT_EQ(a.rate, 130.5);
  EXPECT_EQ(a.count, 3);
  EXPECT_FALSE(a.score);  // NULL
  ASSERT_TRUE(s.step());
  Row b;
  read_columns(s, kRest, b, read_columns(s, kFirst, b));
  EXPECT_EQ(b.name, "msd");
  EXPECT_EQ(b.count, -2);
  ASSERT_TRUE(b.score);
  EXPECT_EQ(*b.score, 0.25);
}

TEST_F(RowColumns, ReadRowLeavesTheFieldsOfNoColumnAtTheirDefaults) {
  const std::string sql = "SELECT " + select_list(kRest) + " FROM t WHERE id = 8";
  Stmt s(db_, sql.c_str());
  ASSERT_TRUE(s.step());
  const Row r = read_row(s, kRest);
  EXPECT_EQ(r.id, 0);
  EXPECT_EQ(r.name, "unset");
  EXPECT_EQ(r.rate, 1000.0);
}

}  // namespace
}  // namespace nlsoft::console
