// StatsCsv: the per-step statistics table (stats.csv): a header line with the column names,
// then one line per row() call. Rank 0 writes; the other ranks only take part in the error
// check, so that a failed write throws on every rank rather than leaving them waiting.
#pragma once
#include <mpi.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dipc {

class StatsCsv {
 public:
  // Collective over `comm` (or serial when MPI is not initialised). Creates the parent
  // directory if needed, truncates `path` and writes the header. Throws std::runtime_error
  // naming the path on every rank if rank 0 cannot, and std::invalid_argument for an empty
  // column list or a column name holding a comma, a quote or a line break.
  // keep_through_step >= 0 continues an existing table instead (a restart): its header must be
  // this one, rows whose first value (the step) is at most keep_through_step stay, later ones
  // are dropped; where the file does not exist a new one is created.
  StatsCsv(const std::string& path, std::vector<std::string> columns, MPI_Comm comm = MPI_COMM_WORLD,
           long keep_through_step = -1);

  // One value of a row: a number (%.10g) or a text (quoted as CSV requires when it holds a
  // comma, a quote or a line break).
  class Cell {
   public:
    Cell(double value);
    Cell(const std::string& text);
    Cell(const char* text) : Cell(std::string(text)) {}
    const std::string& csv() const { return csv_; }

   private:
    std::string csv_;
  };

  // Collective. Writes one line and flushes it, so the table is complete up to the last step
  // if the run is killed. `values` must have one entry per column.
  void row(const std::vector<Cell>& values);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  void check(const std::string& local_error) const;
  // Rank 0: rewrites the table with the kept rows (temporary file + rename), opens it to append.
  std::string continue_table(const std::string& header, long keep_through_step);

  std::string path_;
  std::vector<std::string> columns_;
  MPI_Comm comm_ = MPI_COMM_NULL;  // MPI_COMM_NULL: serial
  bool writes_ = true;             // rank 0
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_{nullptr, &std::fclose};
};

}  // namespace dipc
