package io.stridekit.android.common

/**
 * Android timestamps to stridekit time.
 *
 * `SensorEvent.timestamp` and `Location.elapsedRealtimeNanos` are nanoseconds on the
 * `SystemClock.elapsedRealtimeNanos()` clock (monotonic, counts deep sleep, restarts
 * at 0 on reboot). stridekit takes `t_s`: seconds as a Double on one monotonic clock
 * shared by all streams of an engine. Never go through Float (24-bit mantissa: 1 s
 * resolution after 4.6 hours of uptime) or Int milliseconds.
 */
object SensorClock {
    const val NANOS_PER_SECOND: Long = 1_000_000_000L

    /** Longs of magnitude below 2^53 convert to Double exactly. */
    private const val EXACT_LIMIT: Long = 1L shl 53

    /**
     * Nanoseconds to seconds. Below 2^53 ns (104 days) the result is the correctly
     * rounded quotient; above, whole seconds and the remainder are converted apart, so
     * the error stays within one ulp (~0.1 ns at 100 days) for any Long.
     */
    @JvmStatic
    fun nanosToSeconds(ns: Long): Double =
        if (ns > -EXACT_LIMIT && ns < EXACT_LIMIT) {
            ns.toDouble() / 1e9
        } else {
            (ns / NANOS_PER_SECOND).toDouble() + (ns % NANOS_PER_SECOND).toDouble() / 1e9
        }
}

/**
 * The time base of one tracking session: `t_s = offsetS + elapsedRealtimeNanos / 1e9`.
 *
 * Within one boot `offsetS` is 0 and `t_s` is plain seconds since boot (what the
 * stridekit README uses). A session restored from a snapshot after a reboot must keep
 * `t_s` increasing although elapsedRealtime restarted at 0: [onBoot]
 * places the new boot's clock after the last saved sample, by the wall-clock gap.
 * Persist [state] next to the engine's snapshot. Not thread-safe by itself: the
 * sessions call it under their lock.
 */
class SessionClock(state: State = State()) {
    /**
     * What to persist. `bootEpochMs` identifies the boot the times came from
     * (`System.currentTimeMillis() - SystemClock.elapsedRealtime()`, stable to a few ms
     * within a boot); `lastTs` is the newest `t_s` handed out.
     */
    data class State(
        val offsetS: Double = 0.0,
        val bootEpochMs: Long? = null,
        val lastTs: Double = Double.NEGATIVE_INFINITY,
        val lastElapsedNs: Long = 0L,
    )

    private var offsetS = state.offsetS
    private var bootEpochMs = state.bootEpochMs
    private var lastTs = state.lastTs
    private var lastElapsedNs = state.lastElapsedNs

    /** The state to persist (a copy). */
    val state: State get() = State(offsetS, bootEpochMs, lastTs, lastElapsedNs)

    /** `t_s` of an elapsedRealtime timestamp (nanoseconds). No allocation. */
    fun seconds(elapsedNs: Long): Double {
        val t = offsetS + SensorClock.nanosToSeconds(elapsedNs)
        if (t > lastTs) {
            lastTs = t
            lastElapsedNs = elapsedNs
        }
        return t
    }

    /**
     * Call once at startup with the current boot's epoch (see [State.bootEpochMs]).
     * Returns true when a reboot was detected (a saved boot more than
     * [toleranceMs] away), after which times of the new boot follow the saved ones.
     */
    fun onBoot(bootEpochMs: Long, toleranceMs: Long = 2_000L): Boolean {
        val saved = this.bootEpochMs
        if (saved == null || kotlin.math.abs(bootEpochMs - saved) <= toleranceMs) {
            this.bootEpochMs = saved ?: bootEpochMs
            return false
        }
        // Wall-clock time from the last sample to the new boot; at least 1 ms, as
        // wall clocks can be set backwards.
        val last = if (lastTs.isFinite()) lastTs else offsetS
        val gapS = maxOf(0.001, (bootEpochMs - saved - lastElapsedNs / 1_000_000L) / 1000.0)
        offsetS = last + gapS
        this.bootEpochMs = bootEpochMs
        lastTs = last
        lastElapsedNs = 0L
        return true
    }
}
