package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.NavException
import io.stridekit.PhoneNavigator
import io.stridekit.SampleError
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.PI
import kotlin.math.sin
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertTrue

/** PhoneNavigator from Kotlin: packed IMU records, GNSS, errors, snapshot. */
class NavigatorTest {
    /** 80-byte records: t, accel xyz, gyro xyz, mag xyz (NaN: no magnetometer). */
    private fun imu(seconds: Double, t0: Double = 0.0, walking: Boolean = false, g: Double = 9.81): ByteArray {
        val n = (seconds * 100).toInt()
        val buf = ByteBuffer.allocate(n * 80).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            val t = t0 + i / 100.0
            val bounce = if (walking) 2.5 * sin(2 * PI * 1.8 * t) else 0.0
            listOf(t, 0.0, 0.3 * bounce, g + bounce, 0.0, 0.0, 0.0, 20.0, 0.0, -40.0).forEach { buf.putDouble(it) }
        }
        return buf.array()
    }

    @Test
    fun `a phone at rest stays put and takes GNSS`() {
        PhoneNavigator.withDefaults().use { nav ->
            val r = nav.pushImuPacked(imu(10.0))
            assertTrue(r.rejected.isEmpty(), "${r.rejected.take(2)}")
            assertEquals(0L, assertNotNull(r.latest).steps)
            val e = nav.pushFix(GnssFix(tS = 10.0, latDeg = 46.5, lonDeg = 6.6, horizontalAccuracyM = 4.0))
            assertEquals(46.5, assertNotNull(e.latDeg), 1e-6)
            val saved = nav.snapshot()
            PhoneNavigator.restore(saved).use { again -> assertContentEquals(saved, again.snapshot()) }
        }
    }

    @Test
    fun `bad input is a typed error and changes nothing`() {
        // An app passing g (iOS reports g) is refused from the first sample.
        PhoneNavigator.withDefaults().use { nav ->
            val fresh = nav.snapshot()
            val r = nav.pushImuPacked(imu(1.0, g = 1.0))
            assertEquals(100, r.rejected.size, "g units must be rejected")
            assertTrue(r.rejected[0].reason.contains("g"), r.rejected[0].reason)
            // The typed cause, the same type in every engine's batch result.
            assertTrue(r.rejected[0].error is SampleError.AccelerationNotInMps2, "${r.rejected[0].error}")
            assertContentEquals(fresh, nav.snapshot())
        }
        PhoneNavigator.withDefaults().use { nav ->
            nav.pushImuPacked(imu(2.0))
            val before = nav.snapshot()
            assertFailsWith<NavException.InvalidBuffer> { nav.pushImuPacked(ByteArray(79)) }
            val e = assertFailsWith<NavException.OutOfRange> { nav.pushFix(GnssFix(tS = 3.0, latDeg = 95.0, lonDeg = 0.0)) }
            assertEquals("lat_deg", e.field)
            assertEquals(95.0, e.value)
            // The SDK's sentence, without a doubled prefix.
            assertEquals(e.toString(), e.message)
            assertTrue(e.message.startsWith("lat_deg = 95 is out of range"), e.message)
            assertContentEquals(before, nav.snapshot())
            val bad = assertFailsWith<NavException.InvalidSnapshot> { PhoneNavigator.restore(byteArrayOf(1, 2, 3)) }
            assertEquals(1, Regex("cannot restore").findAll(bad.message).count(), bad.message)
        }
    }
}
