# Writes OUTPUT: a C++ table of every schema/db/NNNN_name.sql file in SQL_DIR, in file-name order.
file(GLOB files ${SQL_DIR}/*.sql)
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
  string(APPEND body "    {${version}, \"${name}\", R\"pslam_sql(${sql})pslam_sql\"},\n")
endforeach()
file(WRITE ${OUTPUT}.tmp "// Generated from schema/db by server/cmake/embed_migrations.cmake; do not edit.
#include \"storage/migrate.hpp\"

namespace pslam::server {

const std::vector<Migration>& EmbeddedMigrations() {
  static const std::vector<Migration> migrations = {
${body}  };
  return migrations;
}

}  // namespace pslam::server
")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
