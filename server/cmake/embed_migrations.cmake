# Writes OUTPUT: a C++ table per engine of every NNNN_name.sql file, in file-name order: SQL_DIR
# for SQLite, SQL_DIR/postgres for PostgreSQL.
function(migration_table dir out_var)
  file(GLOB files ${dir}/*.sql)
  list(SORT files)
  set(body "")
  foreach(f ${files})
    get_filename_component(name ${f} NAME)
    string(REGEX MATCH "^([0-9]+)_" _ ${name})
    if(NOT CMAKE_MATCH_1)
      message(FATAL_ERROR "migration ${name} must be named NNNN_description.sql")
    endif()
    math(EXPR version "${CMAKE_MATCH_1}")
    file(READ ${f} sql)
    string(APPEND body "      {${version}, \"${name}\", R\"pslam_sql(${sql})pslam_sql\"},\n")
  endforeach()
  set(${out_var} "${body}" PARENT_SCOPE)
endfunction()

migration_table(${SQL_DIR} sqlite_body)
migration_table(${SQL_DIR}/postgres postgres_body)
file(WRITE ${OUTPUT}.tmp "// Generated from schema/db by server/cmake/embed_migrations.cmake; do not edit.
#include \"storage/migrate.hpp\"

namespace pslam::server {

const std::vector<Migration>& EmbeddedMigrations(StorageKind kind) {
  static const std::vector<Migration> sqlite = {
${sqlite_body}  };
  static const std::vector<Migration> postgres = {
${postgres_body}  };
  return kind == StorageKind::kPostgres ? postgres : sqlite;
}

}  // namespace pslam::server
")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
