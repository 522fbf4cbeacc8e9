#include "models/vision/tag.h"

#include <cstring>
#include <stdexcept>

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagStandard41h12.h>
}

namespace hcosim::models::vision {

namespace {

struct Known {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr Known kKnown[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
};

const Known& known(const std::string& name) {
  for (const Known& k : kKnown)
    if (name == k.name) return k;
  throw std::invalid_argument("tag family '" + name + "' is not one of tag36h11, tag25h9, tag16h5, tagStandard41h12");
}

}  // namespace

Family::Family(const std::string& name) : name_(name), family_(known(name).create()) {}

Family::~Family() { known(name_).destroy(family_); }

int Family::codes() const { return int(family_->ncodes); }
int Family::border_cells() const { return family_->width_at_border; }
int Family::total_cells() const { return family_->total_width; }

cv::Mat Family::image(int id) const {
  if (id < 0 || id >= codes())
    throw std::invalid_argument(name_ + " has ids 0.." + std::to_string(codes() - 1) + ", not " + std::to_string(id));
  image_u8_t* im = apriltag_to_image(family_, id);
  cv::Mat out(im->height, im->width, CV_8U);
  for (int r = 0; r < im->height; ++r) std::memcpy(out.ptr(r), im->buf + r * im->stride, std::size_t(im->width));
  image_u8_destroy(im);
  return out;
}

}  // namespace hcosim::models::vision
