//! The host's side of the CLAP callbacks: the handler types `clack-host` instantiates, what
//! the plugin asks of the host (callbacks, restarts, flushes, rescans, dirty state) and which
//! thread it asked on.

use clack_extensions::audio_ports::{
    AudioPortRescanFlags, HostAudioPorts, HostAudioPortsImpl, PluginAudioPorts,
};
use clack_extensions::latency::PluginLatency;
use clack_extensions::params::{
    HostParams, HostParamsImplMainThread, HostParamsImplShared, ParamClearFlags, ParamRescanFlags,
    PluginParams,
};
use clack_extensions::state::{HostState, HostStateImpl, PluginState};
use clack_extensions::thread_check::{HostThreadCheck, HostThreadCheckImpl};
use clack_host::prelude::*;
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::OnceLock;
use std::thread::ThreadId;

thread_local! {
    /// Set on the threads [`Instance::render`](crate::Instance::render) processes audio on.
    pub(crate) static IS_AUDIO_THREAD: Cell<bool> = const { Cell::new(false) };
}

/// The host's handler types (`clack_host::host::HostHandlers`).
pub struct Host;

/// Thread-safe host state: requests from the plugin and the plugin's extensions.
pub struct Shared {
    pub(crate) main_thread: ThreadId,
    pub(crate) callback_requested: AtomicBool,
    pub(crate) restart_requested: AtomicBool,
    pub(crate) flush_requested: AtomicBool,
    pub(crate) params: OnceLock<Option<PluginParams>>,
    pub(crate) state: OnceLock<Option<PluginState>>,
    pub(crate) audio_ports: OnceLock<Option<PluginAudioPorts>>,
    pub(crate) latency: OnceLock<Option<PluginLatency>>,
}

impl<'a> SharedHandler<'a> for Shared {
    fn initializing(&self, instance: InitializingPluginHandle<'a>) {
        let _ = self.params.set(instance.get_extension());
        let _ = self.state.set(instance.get_extension());
        let _ = self.audio_ports.set(instance.get_extension());
        let _ = self.latency.set(instance.get_extension());
    }

    fn request_restart(&self) {
        self.restart_requested.store(true, Ordering::SeqCst);
    }

    fn request_process(&self) {}

    fn request_callback(&self) {
        self.callback_requested.store(true, Ordering::SeqCst);
    }
}

impl HostThreadCheckImpl for Shared {
    fn is_main_thread(&self) -> bool {
        std::thread::current().id() == self.main_thread
    }

    fn is_audio_thread(&self) -> bool {
        IS_AUDIO_THREAD.with(Cell::get)
    }
}

impl HostParamsImplShared for Shared {
    fn request_flush(&self) {
        self.flush_requested.store(true, Ordering::SeqCst);
    }
}

/// Main-thread host state: what the plugin told the host.
#[derive(Default)]
pub struct MainThread {
    /// `params.rescan` calls (e.g. after a state load).
    pub rescans: AtomicU32,
    /// `state.mark_dirty` calls.
    pub dirty_marks: AtomicU32,
    /// Set when `is_main_thread` was false inside a main-thread callback.
    pub wrong_thread: AtomicBool,
    pub(crate) main_thread: Option<ThreadId>,
}

impl MainThread {
    fn check_thread(&self) {
        if Some(std::thread::current().id()) != self.main_thread {
            self.wrong_thread.store(true, Ordering::SeqCst);
        }
    }
}

impl MainThreadHandler<'_> for MainThread {}

impl HostParamsImplMainThread for MainThread {
    fn rescan(&self, _flags: ParamRescanFlags) {
        self.check_thread();
        self.rescans.fetch_add(1, Ordering::SeqCst);
    }

    fn clear(&self, _param_id: ClapId, _flags: ParamClearFlags) {
        self.check_thread();
    }
}

impl HostStateImpl for MainThread {
    fn mark_dirty(&self) {
        self.check_thread();
        self.dirty_marks.fetch_add(1, Ordering::SeqCst);
    }
}

impl HostAudioPortsImpl for MainThread {
    fn is_rescan_flag_supported(&self, _flag: AudioPortRescanFlags) -> bool {
        false
    }

    fn rescan(&self, _flags: AudioPortRescanFlags) {
        self.check_thread();
    }
}

impl HostHandlers for Host {
    type Shared<'a> = Shared;
    type MainThread<'a> = MainThread;
    type AudioProcessor<'a> = ();

    fn declare_extensions(builder: &mut HostExtensions<Self>, _shared: &Self::Shared<'_>) {
        builder
            .register::<HostParams>()
            .register::<HostState>()
            .register::<HostAudioPorts>()
            .register::<HostThreadCheck>();
    }
}
