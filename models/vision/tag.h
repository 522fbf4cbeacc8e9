// AprilTag families: the libapriltag family object, its geometry, and its
// tags as images. A tag's size is the edge of its black border
// (`border_cells` cells), as AprilTag and IDL MarkerPose.tag_size_m use it.
#pragma once

#include <string>

#include <opencv2/core.hpp>

struct apriltag_family;

namespace hcosim::models::vision {

class Family {
 public:
  // tag36h11, tag25h9, tag16h5 or tagStandard41h12; throws
  // std::invalid_argument naming the known ones otherwise.
  explicit Family(const std::string& name);
  ~Family();
  Family(const Family&) = delete;
  Family& operator=(const Family&) = delete;

  const std::string& name() const { return name_; }
  int codes() const;         // tags in the family (ids 0 .. codes-1)
  int border_cells() const;  // cells across the black border
  int total_cells() const;   // cells across the whole tag image, white margin included
  // Tag `id`, one pixel per cell, 0 black and 255 white. Throws for a bad id.
  cv::Mat image(int id) const;
  apriltag_family* get() const { return family_; }

 private:
  std::string name_;
  apriltag_family* family_ = nullptr;
};

}  // namespace hcosim::models::vision
