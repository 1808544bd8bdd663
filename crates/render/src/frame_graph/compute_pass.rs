//! One wgpu compute pass for a run of dispatches. wgpu 30 encodes every
//! compute pass into two Vulkan command buffers of its own (the pass's body
//! and the barriers before it), each begun, ended, submitted and reset, and
//! on the H100 beginning them was the largest single item of the recording
//! thread's profile (docs/benchmarks.md, "Session 12: CPU"). So the
//! dispatches of consecutive graph passes go into one compute pass, kept open
//! as long as their encoder is: wgpu still places the barriers each dispatch
//! needs, inside the pass, as it placed them between passes.
//!
//! A pass is ended where something needs the encoder itself (a render pass, a
//! copy, a clear: [`PassContext::encoder`]) and where the encoder is finished
//! (the end of a run of a batched frame, every graph pass of an isolated
//! one). A timed graph pass writes its two timestamps inside the shared pass
//! where the device can ([`wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES`]);
//! where it cannot, it gets a compute pass of its own, timed by the pass's
//! own timestamp writes, as before.
//!
//! Two things differ from a pass each. A pipeline and bind groups set by one
//! graph pass are still set for the next: a pass must set every group its
//! pipeline uses (wgpu checks only that they are compatible). And a
//! dispatch's barriers come after its graph pass's first timestamp, so they
//! count in the pass's GPU time rather than as idle time before it; the
//! first use of each resource in the whole run is prepared before the run,
//! in the buffer wgpu puts before the compute pass.
//!
//! That the barriers between dispatches are there rests on wgpu-core 30:
//! every dispatch is its own usage scope, and the state changes from the
//! dispatch before are recorded right before it (`compute.rs`,
//! `flush_bindings` and `drain_barriers`); storage writes are never treated
//! as ordered, so two writes to one texture get a barrier too. The tests can
//! only show the images are right where the device runs dispatches in order.

use super::PassContext;

/// The counter of compute passes the frame graph began in a frame (each one
/// wgpu encodes into command buffers of its own); geometry and particle
/// nodes, which dispatch as they evaluate, have their own.
pub const COMPUTE_PASSES: &str = "compute passes";

/// The open compute pass and who may add to it.
pub(crate) struct OpenCompute {
    pass: wgpu::ComputePass<'static>,
    /// The timestamp the current graph pass writes when it ends (and the
    /// set it is in), where it wrote its first inside this pass.
    end_query: Option<(wgpu::QuerySet, u32)>,
    /// Whether later graph passes may add to it: not one that belongs to the
    /// graph pass that began it (timed by its own timestamp writes, or meant
    /// to be and out of queries).
    shared: bool,
}

impl OpenCompute {
    /// End the current graph pass's part: its closing timestamp.
    fn close_part(&mut self) {
        if let Some((set, end)) = self.end_query.take() {
            self.pass.write_timestamp(&set, end);
        }
    }
}

impl PassContext<'_> {
    /// The command encoder, for what a compute pass cannot hold: render
    /// passes, copies, clears. The open compute pass ends first: wgpu refuses
    /// an encoder while a pass on it is open ("Encoder is locked").
    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.end_compute();
        self.used_encoder = true;
        &mut self.encoder
    }

    /// A compute pass to dispatch into: the one open on this encoder when
    /// there is one, else a new one. Timed graph passes are timed from their
    /// first dispatch to the end of the graph pass. `label` names a pass only
    /// this graph pass uses (shared ones hold many: "dispatches"). Set every
    /// bind group the pipeline uses: what an earlier graph pass set is still
    /// set.
    pub fn compute_pass(&mut self, label: &str) -> &mut wgpu::ComputePass<'static> {
        let timed = self.timestamps.is_some();
        let inside = self.timestamps_inside_passes;
        let keep = match &self.compute {
            // A pass timed by its own writes is this graph pass's alone
            // (passes that are not theirs were ended in `finish`).
            Some(open) if !open.shared => true,
            Some(_) => !timed || inside,
            None => false,
        };
        if !keep {
            self.end_compute();
            // Without timestamps inside passes a timed graph pass gets its own.
            let own = timed && !inside;
            let timestamp_writes = if own {
                self.next_pair()
                    .map(|(query_set, i)| wgpu::ComputePassTimestampWrites {
                        query_set,
                        beginning_of_pass_write_index: Some(i),
                        end_of_pass_write_index: Some(i + 1),
                    })
            } else {
                None
            };
            let pass = self
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(if own { label } else { "dispatches" }),
                    timestamp_writes,
                })
                .forget_lifetime();
            self.count(COMPUTE_PASSES, 1);
            self.compute = Some(OpenCompute {
                pass,
                end_query: None,
                shared: !own,
            });
        }
        // A timed graph pass's first dispatch in a shared pass: its first timestamp.
        let begins = timed
            && inside
            && self
                .compute
                .as_ref()
                .is_some_and(|open| open.shared && open.end_query.is_none());
        if begins && let Some((set, begin)) = self.next_pair() {
            let open = self.compute.as_mut().expect("opened above");
            open.pass.write_timestamp(set, begin);
            open.end_query = Some((set.clone(), begin + 1));
        }
        &mut self.compute.as_mut().expect("opened above").pass
    }

    /// End the open compute pass (with the current graph pass's closing
    /// timestamp): before the encoder is used directly or finished.
    pub(crate) fn end_compute(&mut self) {
        if let Some(mut open) = self.compute.take() {
            open.close_part();
        }
    }

    /// The graph pass is done: write its closing timestamp, and end a compute
    /// pass only it may use. What stays open goes on to the next graph pass.
    pub(crate) fn close_graph_pass(&mut self) {
        match &mut self.compute {
            Some(open) if open.shared => open.close_part(),
            Some(_) => self.end_compute(),
            None => {}
        }
    }
}
