package io.stridekit.tests

import io.stridekit.android.common.SensorClock
import io.stridekit.android.common.SessionClock
import io.stridekit.android.common.StepCounter
import java.math.BigDecimal
import java.util.Random
import kotlin.math.abs
import kotlin.math.ulp
import kotlin.test.Test
import kotlin.test.assertEquals
import kotlin.test.assertFalse
import kotlin.test.assertTrue

/** The Android adapters' clock conversion and step-counter normalisation (plain Kotlin). */
class AndroidClockTest {
    private fun exact(ns: Long): Double = BigDecimal(ns).divide(BigDecimal(1_000_000_000L)).toDouble()

    @Test
    fun `nanoseconds become correctly rounded seconds below 2^53 ns`() {
        val edges = listOf(0L, 1L, 999_999_999L, 1_000_000_000L, 1_000_000_001L, (1L shl 53) - 1, -(1L shl 53) + 1, -1L)
        val rnd = Random(6)
        val random = (0 until 20_000).map { rnd.nextLong() ushr 11 } // < 2^53
        for (ns in edges + random) assertEquals(exact(ns), SensorClock.nanosToSeconds(ns), "ns = $ns")
    }

    @Test
    fun `beyond 2^53 ns the error stays within one ulp`() {
        val rnd = Random(7)
        val values = listOf(1L shl 53, (1L shl 53) + 1, Long.MAX_VALUE, Long.MIN_VALUE + 1) + (0 until 5_000).map { rnd.nextLong() }
        for (ns in values) {
            val got = SensorClock.nanosToSeconds(ns)
            assertTrue(abs(got - exact(ns)) <= exact(ns).ulp, "ns = $ns: $got vs ${exact(ns)}")
        }
    }

    @Test
    fun `sample spacing survives 200 days of uptime`() {
        // 400 Hz after 200 days since boot: seconds ~1.7e7, ulp ~3.7e-9 s.
        val boot200d = 200L * 86_400L * SensorClock.NANOS_PER_SECOND
        var prev = SensorClock.nanosToSeconds(boot200d)
        for (i in 1..4_000) {
            val t = SensorClock.nanosToSeconds(boot200d + i * 2_500_000L)
            assertTrue(t > prev, "strictly increasing at sample $i")
            assertEquals(0.0025, t - prev, 1e-8)
            prev = t
        }
        // A Float would not even keep the seconds: the reason times stay Long/Double.
        assertEquals(boot200d.toFloat(), (boot200d + 2_500_000L).toFloat())
    }

    @Test
    fun `a session clock continues after a reboot`() {
        val boot1 = 1_790_000_000_000L // epoch ms of the first boot
        val clock = SessionClock()
        assertFalse(clock.onBoot(boot1))
        val last = clock.seconds(3_600L * SensorClock.NANOS_PER_SECOND) // 1 h after boot
        assertEquals(3600.0, last)
        val saved = clock.state

        // Restart of the app, same boot (epoch estimate jitters by a few ms): unchanged.
        SessionClock(saved).also {
            assertFalse(it.onBoot(boot1 + 3))
            assertEquals(3601.0, it.seconds(3_601L * SensorClock.NANOS_PER_SECOND))
        }

        // The device rebooted 10 minutes after the last sample; elapsedRealtime restarts.
        val boot2 = boot1 + 3_600_000L + 600_000L
        val again = SessionClock(saved)
        assertTrue(again.onBoot(boot2))
        val t = again.seconds(5L * SensorClock.NANOS_PER_SECOND)
        assertEquals(3600.0 + 600.0 + 5.0, t, 1e-9)
        assertTrue(t > last)

        // A wall clock set backwards still moves time forward.
        val backwards = SessionClock(saved)
        assertTrue(backwards.onBoot(boot1 - 86_400_000L))
        assertTrue(backwards.seconds(0L) > last)
    }

    @Test
    fun `step counter resets and reboots keep the count monotonic`() {
        val c = StepCounter()
        assertEquals(0L, c.total)
        assertEquals(5_000L, c.onReport(5_000f)) // steps since boot: a base, differences count
        assertEquals(5_010L, c.onReport(5_010f))
        assertEquals(5_010L, c.onReport(Float.NaN))
        assertEquals(5_010L, c.onReport(-1f))
        // The counter went down: reset. The new value is steps since the reset.
        assertEquals(5_017L, c.onReport(7f))
        assertEquals(1, c.state.resets)
        assertEquals(5_020L, c.onReport(10f))

        // Persisted, then the device rebooted and walked 6 000 steps before the first
        // report (more than before: only the explicit reboot notice can tell).
        val restored = StepCounter(c.state)
        restored.onReboot()
        assertEquals(5_020L + 6_000L, restored.onReport(6_000f))
        assertEquals(2, restored.state.resets)
        // Without the notice the same report would count only the difference.
        assertEquals(5_020L + 5_990L, StepCounter(c.state).onReport(6_000f))

        // Floats are exact up to 2^24 steps.
        val big = StepCounter()
        big.onReport(16_777_000f)
        assertEquals(16_777_216L, big.onReport(16_777_216f))
    }
}
