package io.stridekit.android.common

/**
 * Android's TYPE_STEP_COUNTER to a monotonic cumulative count.
 *
 * The sensor reports steps since the last reboot as a Float (`values[0]`), and
 * restarts at 0 when the device reboots (some devices also reset it otherwise). The
 * stridekit tracker takes cumulative counts per session; it treats a count that goes
 * down as a reset but then loses the steps counted between the reset and that report.
 * This normaliser keeps a session-wide count instead: after a decrease the new raw
 * value counts in full (steps since the reset). Persist [state] next to the tracker's
 * snapshot; after a reboot call [onReboot] (or let the decrease be detected).
 */
class StepCounter(state: State = State()) {
    /** `lastRaw` < 0: nothing seen yet. `total` = `offset` + `lastRaw`. */
    data class State(val offset: Long = 0L, val lastRaw: Long = -1L, val resets: Int = 0)

    var state: State = state
        private set

    /** The session-wide count after the latest report (0 before the first). */
    val total: Long get() = state.offset + maxOf(0L, state.lastRaw)

    /**
     * One sensor report; returns the session-wide cumulative count. Floats are exact
     * up to 2^24 = 16.7 million steps; NaN or negative reports are ignored (the last
     * total is returned).
     */
    fun onReport(raw: Float): Long {
        if (raw.isNaN() || raw < 0f) return total
        val r = raw.toLong()
        val s = state
        state = when {
            s.lastRaw < 0 -> s.copy(lastRaw = r)
            r >= s.lastRaw -> s.copy(lastRaw = r)
            // The counter went down: a reset. The new value counts since the reset.
            else -> State(offset = s.offset + s.lastRaw, lastRaw = r, resets = s.resets + 1)
        }
        return total
    }

    /** The device rebooted since [state] was saved: the next report counts from 0. */
    fun onReboot() {
        val s = state
        if (s.lastRaw >= 0) state = State(offset = s.offset + s.lastRaw, lastRaw = 0L, resets = s.resets + 1)
    }
}
