#include "rasm/pipeline/MapperStage.h"

#include <cstdio>

namespace rasm::pipeline {

void CsvRow::separate() {
  if (!m_first) m_text += ',';
  m_first = false;
}

CsvRow& CsvRow::add(long long v) {
  separate();
  m_text += std::to_string(v);
  return *this;
}

CsvRow& CsvRow::add(double v, int decimals) {
  separate();
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  m_text += buf;
  return *this;
}

CsvRow& CsvRow::add(const std::string& v) {
  separate();
  for (char c : v) m_text += (c == ',' ? ';' : (c == '\n' || c == '\r') ? ' ' : c);
  return *this;
}

}  // namespace rasm::pipeline
