#pragma once
// A table's row read into a struct through one list of columns, each the
// SELECT expression beside the field it fills. The SELECT list and the
// reader are both made from that list, so a column added, moved or dropped
// cannot put them out of step; a hand-kept column string and a reader by
// position (text(3), int64(4), ...) could, and nothing would say so.
#include <cstddef>
#include <optional>
#include <string>
#include <type_traits>

#include "app/record/sqlite.hpp"

namespace nlsoft::console {

template <class Row>
struct Column {
  const char* sql;                              // the SELECT expression: "id", "ifnull(ended_at,'')"
  void (*read)(const Stmt& s, int col, Row& row);  // fills the field from result column `col`
};

template <class>
struct FieldOf;
template <class R, class T>
struct FieldOf<T R::*> {
  using Row = R;
  using Type = T;
};

namespace detail {
template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

template <class T>
T column_value(const Stmt& s, int col) {
  if constexpr (std::is_same_v<T, std::string>) {
    return s.text(col);
  } else if constexpr (std::is_floating_point_v<T>) {
    return T(s.real(col));
  } else {
    static_assert(std::is_integral_v<T>, "a column reads into a string, a number or an optional number");
    return T(s.int64(col));
  }
}
}  // namespace detail

// The reader of a plain field: text into a string, a real into a floating
// point field, an integer into any integer field (cast, as SQLite's int64
// is narrowed by the field), and NULL into an optional as empty.
template <auto field>
void read_field(const Stmt& s, int col, typename FieldOf<decltype(field)>::Row& row) {
  using T = typename FieldOf<decltype(field)>::Type;
  if constexpr (detail::IsOptional<T>::value) {
    row.*field = s.is_null(col) ? T() : T(detail::column_value<typename T::value_type>(s, col));
  } else {
    row.*field = detail::column_value<T>(s, col);
  }
}

// "a,b,c": the columns' expressions for a SELECT.
template <class Row, size_t N>
std::string select_list(const Column<Row> (&columns)[N]) {
  std::string out;
  for (const Column<Row>& c : columns) out += (out.empty() ? "" : ",") + std::string(c.sql);
  return out;
}

// Fills `row` from the result columns first, first + 1, ... in the list's
// order; the next column's index, for a list that goes on with another.
template <class Row, size_t N>
int read_columns(const Stmt& s, const Column<Row> (&columns)[N], Row& row, int first = 0) {
  for (const Column<Row>& c : columns) c.read(s, first++, row);
  return first;
}

// A row made from its defaults and the list's columns.
template <class Row, size_t N>
Row read_row(const Stmt& s, const Column<Row> (&columns)[N]) {
  Row row;
  read_columns(s, columns, row);
  return row;
}

}  // namespace nlsoft::console
