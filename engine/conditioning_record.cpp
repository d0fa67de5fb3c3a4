#include "engine/conditioning_record.h"

#include <sstream>

namespace napkin::engine {

std::string FilterDescription(const ChannelConditioning& record) {
  std::ostringstream text;
  if (record.filter_cfc)
    text << "CFC " << *record.filter_cfc;
  else if (record.filter_skipped_prefiltered)
    text << "none, prefiltered at CFC " << *record.prefiltered_cfc;
  else
    text << "none";
  return text.str();
}

}  // namespace napkin::engine
