#pragma once
// Small but complete files of every format facesr reads, written by the
// project's own writers (save_rig, save_sr_model, SequenceWriter, ...): the
// fuzzers' seeds and the round-trip cases of the loader tests. Small, so a
// fuzzer runs thousands of them a second; complete, so every field of each
// format is present and mutations reach every parser.
#include <string>
#include <vector>

#include "dataset/dataset_io.h"
#include "rig/rig.h"

namespace facesr::tiny {

// tiny_rig.cpp (no dependencies beyond the rig format, for the fuzzers):
// 4 surface vertices, 2 shapes, 1 muscle, HR 2 tets, LR 1 tet, teeth, jaw
// shape, predeformation: every Rig field set and mutually consistent.
Rig rig();
// The header of the tiny dataset sequence (the partial-file target resumes
// against it).
DatasetHeader dataset_header();

// Writes the seed files of each fuzz target into `dir`/<target>/, one file
// per case (e.g. rig/tiny.rig, model/plain.fsm, model/pe_rows.fsm, ...).
// `livelink_dir`, if not empty, adds the first rows of each real take there
// (../shared/data/livelink) to the Live Link seeds. Returns the files written.
std::vector<std::string> write_seed_files(const std::string& dir, const std::string& livelink_dir = "");

}  // namespace facesr::tiny
