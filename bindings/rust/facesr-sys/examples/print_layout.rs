//! Prints the size of every facesr-sys struct and the offset and size of each
//! field, in the format of the consistency check (bindings/check):
//!   struct <name> size <bytes>
//!   field <struct> <field> offset <bytes> size <bytes>
//!
//! Offsets are measured on a zeroed value (address of the field minus address
//! of the struct) rather than with `offset_of!`, which needs rustc 1.77;
//! zeroed is a valid value of each of these plain-data structs (a null
//! `device_name` included). Each list must name exactly the struct's fields
//! (else it does not compile), and the check compares them with the header's.
use facesr_sys::*;
use std::mem::{size_of, size_of_val, zeroed};

macro_rules! layout {
    ($t:ident { $($f:ident),* $(,)? }) => {{
        let v: $t = unsafe { zeroed() };
        // An exhaustive pattern: it fails to compile if the struct has a
        // field this list lacks, so the list is exactly the struct's fields.
        let $t { $($f: _),* } = &v;
        let base = &v as *const $t as usize;
        println!("struct {} size {}", stringify!($t), size_of::<$t>());
        $(
            let at = &v.$f as *const _ as usize;
            println!("field {} {} offset {} size {}", stringify!($t), stringify!($f), at - base, size_of_val(&v.$f));
        )*
    }};
}

fn main() {
    layout!(facesr_rig_info {
        struct_size,
        num_blendshapes,
        num_surface_vertices,
        num_surface_triangles,
        num_lr_nodes,
        num_muscles,
        checksum,
        jaw_pivot,
        jaw_axis,
    });
    layout!(facesr_model_info { struct_size, rig_checksum, num_lr_nodes, num_surface_vertices, num_parameters });
    layout!(facesr_context_def { struct_size, device_index, device_name, solver, inference, split_device, lr_precision });
    layout!(facesr_spring_def { struct_size, vertex, target, stiffness });
    layout!(facesr_sphere_def { struct_size, centre, radius, stiffness });
    layout!(facesr_frame_stats {
        struct_size,
        frame,
        simulation_ms,
        inference_ms,
        total_ms,
        newton_iterations,
        cg_iterations,
        relative_residual,
        simulation_status,
        inverted_tets,
        recoveries,
    });
}
