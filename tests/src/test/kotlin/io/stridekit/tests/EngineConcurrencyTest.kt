package io.stridekit.tests

import io.stridekit.FootNavigator
import io.stridekit.FootOutput
import io.stridekit.GnssFix
import io.stridekit.NavException
import io.stridekit.PhoneNavigator
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicLong
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertTrue

/**
 * Four threads pushing into one PhoneNavigator / FootNavigator (PaceTracker: see
 * ConcurrencyTest): calls serialise, nothing crashes, every sample is either accepted
 * or reported rejected, and the state stays consistent (snapshot round trip).
 *
 * Sample times come from a shared counter, but threads race between reserving a block
 * of times and pushing it, so a block can arrive after a later one: its samples are
 * rejected (time not increasing), never a crash.
 */
class EngineConcurrencyTest {
    private class Counts {
        val pushed = AtomicInteger()
        val accepted = AtomicInteger()
        val rejected = AtomicInteger()
        val unexpected = AtomicInteger()

        fun add(n: Int, rejectedN: Int) {
            pushed.addAndGet(n); rejected.addAndGet(rejectedN); accepted.addAndGet(n - rejectedN)
        }

        fun check(what: String) {
            assertEquals(0, unexpected.get(), "$what: unexpected exceptions")
            assertEquals(pushed.get(), accepted.get() + rejected.get(), "$what: every sample accepted or rejected")
            assertTrue(accepted.get() > pushed.get() / 4, "$what: accepted ${accepted.get()} of ${pushed.get()}")
        }
    }

    private fun hammer(threads: Int, rounds: Int, counts: Counts, round: (thread: Int, i: Int) -> Unit) {
        val start = CountDownLatch(1)
        val pool = Executors.newFixedThreadPool(threads)
        repeat(threads) { k ->
            pool.execute {
                start.await()
                try {
                    for (i in 0 until rounds) round(k, i)
                } catch (e: Throwable) {
                    counts.unexpected.incrementAndGet()
                    e.printStackTrace()
                }
            }
        }
        start.countDown()
        pool.shutdown()
        assertTrue(pool.awaitTermination(120, TimeUnit.SECONDS), "threads finished")
    }

    @Test
    fun `four threads pushing into one phone navigator`() {
        val block = 20
        val imuClock = AtomicLong(0)
        val fixClock = AtomicLong(0)
        val c = Counts()
        PhoneNavigator.withDefaults().use { nav ->
            hammer(4, 150, c) { k, i ->
                val first = imuClock.getAndAdd(block.toLong())
                val b = ByteBuffer.allocate(block * 80).order(ByteOrder.LITTLE_ENDIAN)
                for (j in 0 until block) {
                    val t = (first + j) / 100.0
                    listOf(t, 0.05, 0.02, 9.81, 0.001, -0.002, 0.0, 20.0, 0.0, -40.0).forEach { b.putDouble(it) }
                }
                c.add(block, nav.pushImuPacked(b.array()).rejected.size)
                if (i % 5 == 0) {
                    val t = fixClock.incrementAndGet().toDouble()
                    c.pushed.incrementAndGet()
                    try {
                        nav.pushFix(GnssFix(tS = t, latDeg = 46.5, lonDeg = 6.6, horizontalAccuracyM = 5.0))
                        c.accepted.incrementAndGet()
                    } catch (e: NavException) {
                        c.rejected.incrementAndGet()
                    }
                }
                if (k == 0 && i % 30 == 7) PhoneNavigator.restore(nav.snapshot()).close()
                nav.estimate()
            }
            c.check("PhoneNavigator")
            val saved = nav.snapshot()
            PhoneNavigator.restore(saved).use { assertContentEquals(saved, it.snapshot()); assertEquals(nav.estimate(), it.estimate()) }
        }
    }

    @Test
    fun `four threads pushing into one foot navigator`() {
        val block = 40
        val clock = AtomicLong(0)
        val c = Counts()
        val produced = AtomicLong(0)
        FootNavigator.withDefaults().use { nav ->
            hammer(4, 150, c) { k, i ->
                val first = clock.getAndAdd(block.toLong())
                val b = ByteBuffer.allocate(block * 56).order(ByteOrder.LITTLE_ENDIAN)
                for (j in 0 until block) {
                    val t = (first + j) * 0.005
                    listOf(t, 0.02, -0.01, 9.81, 0.001, -0.002, 0.0005).forEach { b.putDouble(it) }
                }
                val r = nav.pushPacked(b.array(), if (i % 2 == 0) FootOutput.ALL else FootOutput.LATEST_ONLY)
                c.add(block, r.rejected.size)
                produced.addAndGet(r.produced.toLong())
                if (k == 1 && i % 30 == 11) FootNavigator.restore(nav.snapshot()).close()
                nav.estimate()
            }
            c.check("FootNavigator")
            assertTrue(produced.get() <= c.accepted.get(), "estimates produced ${produced.get()} <= accepted ${c.accepted.get()}")
            val saved = nav.snapshot()
            FootNavigator.restore(saved).use { assertContentEquals(saved, it.snapshot()); assertEquals(nav.estimate(), it.estimate()) }
        }
    }
}
